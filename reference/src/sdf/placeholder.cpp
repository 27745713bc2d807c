// Replaced by the reference SDF builders.
