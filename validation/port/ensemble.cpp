// The ensemble consistency test (ensemble.hpp; docs/port-validation.md "Method").
#include "ensemble.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
  return f;
}

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

double value_of(const Observables& run, const std::string& name) {
  for (std::size_t k = 0; k < run.names.size(); ++k)
    if (run.names[k] == name) return run.values[k];
  throw std::runtime_error("the run has no observable '" + name + "'");
}

}  // namespace

Baseline fit_baseline(const std::string& scene, const std::vector<Observables>& members, const EnsembleRule& rule) {
  if (members.size() < 3) throw std::invalid_argument("an ensemble needs at least 3 members");
  const auto& all = members.front().names;
  const auto m = static_cast<Eigen::Index>(members.size());
  Eigen::MatrixXd x(m, static_cast<Eigen::Index>(all.size()));
  for (Eigen::Index i = 0; i < m; ++i) {
    if (members[static_cast<std::size_t>(i)].names != all) throw std::invalid_argument("members with different observables");
    for (std::size_t j = 0; j < all.size(); ++j) x(i, static_cast<Eigen::Index>(j)) = members[static_cast<std::size_t>(i)].values[j];
  }
  Baseline b;
  b.scene = scene;
  b.rule = rule;
  b.fit_members = static_cast<int>(m);
  const Eigen::VectorXd mean = x.colwise().mean();
  std::vector<Eigen::Index> kept;
  for (std::size_t j = 0; j < all.size(); ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    const double sd = std::sqrt((x.col(c).array() - mean(c)).square().sum() / static_cast<double>(m - 1));
    // A spread below 1e-12 of the value is round-off, not chaos: such an observable is the same
    // in every member and cannot be standardised.
    if (sd > 1e-12 * std::max(std::abs(mean(c)), 1e-300)) kept.push_back(c);
    else b.constant_names.push_back(all[j]);
  }
  const auto n = static_cast<Eigen::Index>(kept.size());
  b.mean.resize(n);
  b.stddev.resize(n);
  Eigen::MatrixXd z(m, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index c = kept[static_cast<std::size_t>(k)];
    b.names.push_back(all[static_cast<std::size_t>(c)]);
    b.mean(k) = mean(c);
    b.stddev(k) = std::sqrt((x.col(c).array() - mean(c)).square().sum() / static_cast<double>(m - 1));
    z.col(k) = (x.col(c).array() - b.mean(k)) / b.stddev(k);
  }
  const Eigen::MatrixXd correlation = z.transpose() * z / static_cast<double>(m - 1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(correlation);
  const Eigen::VectorXd values = eig.eigenvalues().reverse();  // largest first
  const Eigen::MatrixXd vectors = eig.eigenvectors().rowwise().reverse();
  const double total = values.sum();
  Eigen::Index pcs = 0;
  double explained = 0.0;
  while (pcs < n && explained < rule.variance_kept * total) explained += values(pcs++);
  b.eigenvalues = values.head(pcs);
  b.loadings = vectors.leftCols(pcs);
  return b;
}

Eigen::VectorXd standardised(const Baseline& b, const Observables& run) {
  Eigen::VectorXd z(static_cast<Eigen::Index>(b.names.size()));
  for (std::size_t k = 0; k < b.names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    z(i) = (value_of(run, b.names[k]) - b.mean(i)) / b.stddev(i);
  }
  return z;
}

Eigen::VectorXd pc_scores(const Baseline& b, const Observables& run) {
  return (b.loadings.transpose() * standardised(b, run)).array() / b.eigenvalues.array().sqrt();
}

Verdict judge(const Baseline& b, const std::vector<Observables>& runs) {
  Verdict v;
  v.scores.resize(b.eigenvalues.size(), static_cast<Eigen::Index>(runs.size()));
  for (std::size_t r = 0; r < runs.size(); ++r) v.scores.col(static_cast<Eigen::Index>(r)) = pc_scores(b, runs[r]);
  for (Eigen::Index k = 0; k < v.scores.rows(); ++k) {
    const int beyond = static_cast<int>((v.scores.row(k).array().abs() > b.rule.sigma).count());
    if (beyond >= b.rule.runs_needed) v.failing_pcs.push_back(static_cast<int>(k));
  }
  v.pass = static_cast<int>(v.failing_pcs.size()) < b.rule.min_failing_pcs;
  return v;
}

std::pair<double, std::size_t> false_positive_rate(const Baseline& b, const std::vector<Observables>& held_out) {
  const std::size_t n = held_out.size();
  std::vector<Eigen::VectorXd> scores;
  for (const auto& run : held_out) scores.push_back(pc_scores(b, run));
  std::size_t triples = 0, failed = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        ++triples;
        int failing = 0;
        for (Eigen::Index c = 0; c < b.eigenvalues.size(); ++c) {
          const int beyond = (std::abs(scores[i](c)) > b.rule.sigma) + (std::abs(scores[j](c)) > b.rule.sigma) +
                             (std::abs(scores[k](c)) > b.rule.sigma);
          failing += beyond >= b.rule.runs_needed ? 1 : 0;
        }
        failed += failing >= b.rule.min_failing_pcs ? 1 : 0;
      }
  return {triples > 0 ? static_cast<double>(failed) / static_cast<double>(triples) : 0.0, triples};
}

void write_baseline(const fs::path& dir, const Baseline& b) {
  AtomicFileWriter w(dir / (b.scene + ".baseline.csv"));
  auto& o = w.stream();
  for (const auto& line : b.provenance) o << "# " << line << "\n";
  o << "scene," << b.scene << "\nparticles," << b.particle_count << "\nradius_sum," << g17(b.radius_sum)
    << "\nfit_members," << b.fit_members << "\nrule,sigma," << g17(b.rule.sigma) << ",runs_needed,"
    << b.rule.runs_needed << ",min_failing_pcs," << b.rule.min_failing_pcs << ",variance_kept,"
    << g17(b.rule.variance_kept) << "\nconstant";
  for (const auto& name : b.constant_names) o << "," << name;
  o << "\nobservable";
  for (const auto& name : b.names) o << "," << name;
  o << "\nmean";
  for (Eigen::Index k = 0; k < b.mean.size(); ++k) o << "," << g17(b.mean(k));
  o << "\nstd";
  for (Eigen::Index k = 0; k < b.stddev.size(); ++k) o << "," << g17(b.stddev(k));
  o << "\n";
  for (Eigen::Index c = 0; c < b.eigenvalues.size(); ++c) {
    o << "pc," << g17(b.eigenvalues(c));
    for (Eigen::Index k = 0; k < b.loadings.rows(); ++k) o << "," << g17(b.loadings(k, c));
    o << "\n";
  }
  w.commit();
}

void write_members(const fs::path& dir, const std::string& scene, const std::vector<long>& seeds,
                   const std::vector<bool>& held_out, const std::vector<Observables>& members) {
  AtomicFileWriter w(dir / (scene + ".members.csv"));
  auto& o = w.stream();
  o << "seed,role";
  for (const auto& name : members.front().names) o << "," << name;
  o << "\n";
  for (std::size_t i = 0; i < members.size(); ++i) {
    o << seeds[i] << "," << (held_out[i] ? "held-out" : "fit");
    for (const double v : members[i].values) o << "," << g17(v);
    o << "\n";
  }
  w.commit();
}

Baseline read_baseline(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the baseline");
  Baseline b;
  std::string line;
  std::vector<std::vector<double>> pcs;
  std::vector<double> mean, sd;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      b.provenance.push_back(line.substr(line.size() > 1 ? 2 : 1));
      continue;
    }
    const auto f = split(line);
    const std::string& key = f[0];
    auto nums = [&](std::size_t from) {
      std::vector<double> v;
      for (std::size_t k = from; k < f.size(); ++k) v.push_back(std::stod(f[k]));
      return v;
    };
    try {
      if (key == "scene") b.scene = f.at(1);
      else if (key == "particles") b.particle_count = std::stoul(f.at(1));
      else if (key == "radius_sum") b.radius_sum = std::stod(f.at(1));
      else if (key == "fit_members") b.fit_members = std::stoi(f.at(1));
      else if (key == "rule") {
        b.rule.sigma = std::stod(f.at(2));
        b.rule.runs_needed = std::stoi(f.at(4));
        b.rule.min_failing_pcs = std::stoi(f.at(6));
        b.rule.variance_kept = std::stod(f.at(8));
      } else if (key == "constant") b.constant_names.assign(f.begin() + 1, f.end());
      else if (key == "observable") b.names.assign(f.begin() + 1, f.end());
      else if (key == "mean") mean = nums(1);
      else if (key == "std") sd = nums(1);
      else if (key == "pc") pcs.push_back(nums(1));
      else throw std::runtime_error("unknown key '" + key + "'");
    } catch (const std::exception& e) {
      throw std::runtime_error(file.string() + ":" + std::to_string(number) + ": " + e.what() +
                               " (expected a baseline written by ppohdem validate --save-baseline)");
    }
  }
  const auto n = static_cast<Eigen::Index>(b.names.size());
  if (b.scene.empty() || n == 0 || static_cast<Eigen::Index>(mean.size()) != n ||
      static_cast<Eigen::Index>(sd.size()) != n || pcs.empty()) {
    throw std::runtime_error(file.string() + ": incomplete baseline (expected scene, observable, mean, std, pc lines)");
  }
  b.mean = Eigen::Map<Eigen::VectorXd>(mean.data(), n);
  b.stddev = Eigen::Map<Eigen::VectorXd>(sd.data(), n);
  b.eigenvalues.resize(static_cast<Eigen::Index>(pcs.size()));
  b.loadings.resize(n, static_cast<Eigen::Index>(pcs.size()));
  for (std::size_t c = 0; c < pcs.size(); ++c) {
    if (static_cast<Eigen::Index>(pcs[c].size()) != n + 1) throw std::runtime_error(file.string() + ": a pc line of the wrong length");
    b.eigenvalues(static_cast<Eigen::Index>(c)) = pcs[c][0];
    for (Eigen::Index k = 0; k < n; ++k) b.loadings(k, static_cast<Eigen::Index>(c)) = pcs[c][static_cast<std::size_t>(k) + 1];
  }
  return b;
}

std::vector<Observables> read_members(const fs::path& file, const std::string& role) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::string line;
  std::vector<std::string> header;
  std::vector<Observables> out;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto f = split(line);
    if (header.empty()) {
      header = f;
      continue;
    }
    if (!role.empty() && f.at(1) != role) continue;
    Observables o;
    o.names.assign(header.begin() + 2, header.end());
    for (std::size_t k = 2; k < f.size(); ++k) o.values.push_back(std::stod(f[k]));
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace ppohdem::port
