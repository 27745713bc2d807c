// The scene's insertions during a run (insertion_run.hpp; docs/objects.md "Particle insertion").
#include "ppohdem/dem/insertion_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::dem {

InsertionRun::InsertionRun(const SimulationSetup& setup, const std::vector<InsertSpec>& specs, std::filesystem::path file,
                           std::string header, bool writer)
    : setup_(setup), specs_(specs), file_(std::move(file)), header_(std::move(header)), writer_(writer) {
  record_.counters.resize(specs_.size());
}

void InsertionRun::at_step(DemEngine& engine) {
  const auto started = std::chrono::steady_clock::now();
  insert_due(engine);
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

void InsertionRun::insert_due(DemEngine& engine) {
  const long step = engine.step_count();
  std::vector<std::size_t> due;  // the tables with an event now
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const InsertSchedule& s = specs_[i].schedule;
    const InsertCounters& c = record_.counters[i];
    if ((s.total < 0 || c.requested < s.total) && s.has_event(c.events) && s.step_of(c.events) <= step) due.push_back(i);
  }
  if (due.empty()) return;
  // What the events need of the system, on every rank (collective), without gathering it: the
  // largest id and radius, and the particles within reach of the regions. The reach is taken
  // for the largest radius this step's events can see (those present or any to be drawn),
  // so it holds every particle each event's own, smaller reach can touch.
  const DemEngine::Extent extent = engine.particle_extent();
  double largest = extent.largest_radius;  // of the system, grown by each event's particles
  double largest_bound = largest;
  for (const std::size_t i : due) largest_bound = std::max(largest_bound, specs_[i].sizes.largest());
  std::vector<DemEngine::CentreBox> reach;
  for (const std::size_t i : due) {
    const auto [lo, hi] = insert_reach(specs_[i], largest_bound);
    reach.push_back({lo, hi});
  }
  Particles all = engine.particles_in(reach);  // then the new particles, appended
  const std::size_t before = all.size();
  std::int64_t next_id = extent.largest_id + 1;
  const double time = engine.time();
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const InsertSpec& spec = specs_[i];
    InsertCounters& c = record_.counters[i];
    // An event's step passed without a call cannot happen in a run (every step calls this);
    // `<=` only makes a missed one happen now rather than never.
    // Once `total` is reached the events end (no rows of zero particles).
    const auto open = [&] { return spec.schedule.total < 0 || c.requested < spec.schedule.total; };
    while (open() && spec.schedule.has_event(c.events) && spec.schedule.step_of(c.events) <= step) {
      const long wanted = spec.schedule.wanted(c.events, c.requested, setup_.dt);
      const std::int64_t inserted0 = c.inserted, failed0 = c.failed;
      Particles added = insert_event(spec, wanted, c, all, largest, setup_.boundaries, time, next_id);
      for (const Particle& p : added) largest = std::max(largest, p.radius);
      all.insert(all.end(), added.begin(), added.end());
      c.requested += wanted;
      ++c.events;
      char row[256];
      std::snprintf(row, sizeof row, "%ld,%.17g,%zu,%ld,%lld,%lld,%lld,%lld", step, time, i, wanted,
                    static_cast<long long>(c.inserted - inserted0), static_cast<long long>(c.failed - failed0),
                    static_cast<long long>(c.inserted), static_cast<long long>(c.failed));
      record_.rows.emplace_back(row);
      if (writer_ && c.failed > failed0) {
        std::fprintf(stderr, "warning: %s at step %ld (t = %g s): %lld of %ld particles could not be inserted "
                     "(no free place in %ld attempts each; counted in insertions.csv)\n",
                     spec.name.c_str(), step, time, static_cast<long long>(c.failed - failed0), wanted, spec.attempts);
      }
    }
  }
  if (all.size() == before) return;
  const Particles added(all.begin() + static_cast<std::ptrdiff_t>(before), all.end());
  engine.insert_particles(added);
  if (step == 0) return;  // step 0: part of the initial state
  for (const Particle& p : added) {  // the energy brought in, as the engines sum it (engine.hpp)
    const Material& m = setup_.material_at(p.material);
    const double mass = m.mass(p.radius);
    record_.kinetic += 0.5 * mass * p.velocity.squaredNorm();
    record_.rotational += 0.5 * m.moment_of_inertia(p.radius) * p.angular_velocity.squaredNorm();
    record_.gravitational += -(mass * setup_.gravity.dot(p.position));
  }
}

Energies InsertionRun::input() const {
  Energies e;
  e.kinetic = record_.kinetic;
  e.rotational = record_.rotational;
  e.gravitational = record_.gravitational;
  return e;
}

std::int64_t InsertionRun::inserted() const {
  std::int64_t n = 0;
  for (const InsertCounters& c : record_.counters) n += c.inserted;
  return n;
}

std::int64_t InsertionRun::failed() const {
  std::int64_t n = 0;
  for (const InsertCounters& c : record_.counters) n += c.failed;
  return n;
}

void InsertionRun::flush() const {
  if (!writer_ || !active()) return;
  AtomicFileWriter writer(file_);
  std::ostream& out = writer.stream();
  out << "# " << header_ << '\n';
  out << "step,time,insert,requested,inserted,failed,total_inserted,total_failed\n";
  for (const std::string& row : record_.rows) out << row << '\n';
  writer.commit();
}

void InsertionRun::restore(const InsertionRecord& record, const std::string& source) {
  if (record.counters.size() != specs_.size()) {
    throw InputError(source, 0, "checkpoint: " + std::to_string(record.counters.size()) +
                                    " [[insert]] tables, the scene has " + std::to_string(specs_.size()) +
                                    " (the scene was changed?)");
  }
  record_ = record;
}

}  // namespace ppohdem::dem
