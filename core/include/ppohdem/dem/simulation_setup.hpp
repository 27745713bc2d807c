#pragma once
/// \file simulation_setup.hpp
/// Everything an engine needs to start, independent of any file format: the scene reader
/// (scene.hpp) produces one, tests build them directly. Copyable (boundaries are shared and
/// immutable).
#include <string>
#include <variant>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

using ContactLaw = std::variant<LinearSpringDashpot, HertzMindlin>;

struct SimulationSetup {
  double dt = 0.0;                 ///< time step [s]
  Vec3 gravity = Vec3::Zero();     ///< g [m/s^2]
  Material material;
  ContactLaw law;
  Particles particles;
  BoundaryList boundaries;         ///< walls (and later rigid objects)
  bool allow_initial_overlap = false;  ///< accept overlaps > 1% of the smaller radius
  bool force_time_step = false;        ///< accept dt above the stability limit (--force)
  std::string source;              ///< where it came from (scene file), for messages
};

/// A dt limit and how it was obtained (for the error message).
struct TimeStepLimit {
  double limit = 0.0;  ///< [s]
  std::string reason;  ///< e.g. "0.2 * Rayleigh time 4.33e-05 s of the smallest particle"
};

/// Rayleigh time of a sphere: T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766) [s]
/// (Li, Xu & Thornton 2005; Thornton & Randall 1988).
double rayleigh_time(double radius, const Material& material);

/// Hertz-Mindlin: 0.2 T_R(R_min) (the customary 20% of the Rayleigh time; LIGGGHTS warns
/// above it). Linear: 0.2 pi sqrt(m*_min / k_n), 20% of the undamped half period of the
/// lightest pair (Verlet is unstable above 2/omega_0 = 0.64 of it; 0.2 keeps ~15 steps per
/// contact, the usual accuracy rule). m*_min = m_min/2 (pair), also covering walls (m* = m).
TimeStepLimit time_step_limit(const SimulationSetup& setup);

/// Validates a setup before a run; throws InputError naming setup.source and the record:
/// dt > 0 and finite; radius > 0 and every value finite; ids unique; material ranges;
/// dt <= time_step_limit (unless force_time_step; the message gives the limit); no pair
/// overlapping by more than 1% of the smaller radius (unless allow_initial_overlap).
void validate_setup(const SimulationSetup& setup);

/// Pairs (index i < index j) overlapping by more than `fraction` of the smaller radius.
/// Sort-and-sweep along x: O(N log N + N k).
std::vector<std::pair<std::size_t, std::size_t>> overlapping_pairs(const Particles& particles,
                                                                   double fraction);

}  // namespace ppohdem::dem
