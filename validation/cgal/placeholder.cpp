// Replaced by the CGAL oracle.
