// The measured choice (docs/stages/pack.md "Levels kept"): the error model proves a level from
// its switch distance on, but the image a client draws is what counts, so each band start keeps
// the candidate with the fewest primitives whose shipped file passes the image check there.
// Candidates are measured in an order that skips what cannot win: a coarser level of the chain
// has a larger epsilon, so the levels after a failure are not measured.
#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "stages/pack/level_choice.h"

namespace sylva::pack {

namespace {

// How far the measured choice looks for an impostor that fails at its own distance: up to
// 1.25^8 = 5.96 x that distance, in steps of 1.25.
constexpr int kImpostorFartherSteps = 8;
constexpr double kImpostorFartherFactor = 1.25;

// One measured choice over the prepared candidates: the decisions so far (`out_`), the current
// level (`c_`, the one kept last), and the files already encoded for the meter.
class MeasuredChoice {
 public:
  MeasuredChoice(Prepared& p, const PackOptions& options, LevelMeter& meter)
      : p_(p), options_(options), meter_(meter), cand_(p.candidates), n_(cand_.size()) {
    has_impostor_ = cand_.back().impostor;
    meshes_ = has_impostor_ ? n_ - 1 : n_;
    keep_at_most_ = 1 - options.min_saving;
    out_.resize(n_);
    for (std::size_t j = 0; j < n_; ++j) {
      out_[j].impostor = cand_[j].impostor;
      out_[j].source_level = cand_[j].source_level;
      out_[j].switch_distance_m = cand_[j].switch_distance_m;
      out_[j].primitives = cand_[j].primitives;
    }
    files_.resize(n_);
    settled_.assign(n_, 0);
  }

  std::vector<LevelChoice> run() {
    // 1. Level 0: the finest, drawn nearest; measured at its own switch distance (its coarsest
    // grid that passes there, else its own grid), and the measurement recorded.
    out_[0].kept = true;
    if (!coarsest_grid(0, out_[0].switch_distance_m))
      out_[0].measured = measure(0, out_[0].switch_distance_m).error;
    // 2. Each band start after the current level's, nearest first, until the impostor is kept.
    for (const double b : band_starts()) {
      if (cand_[c_].impostor) break;  // nothing has fewer primitives
      if (!(b > out_[c_].switch_distance_m)) continue;
      decide_band(b);
    }
    // 3. An impostor that failed everywhere so far, farther out.
    keep_impostor_farther();
    // 4. The kept levels' files as shipped.
    ship_kept_levels();
    return std::move(out_);
  }

 private:
  // Every further candidate's own switch distance, sorted, once each.
  std::vector<double> band_starts() const {
    std::vector<double> starts;
    for (std::size_t j = 1; j < n_; ++j) starts.push_back(cand_[j].switch_distance_m);
    std::sort(starts.begin(), starts.end());
    starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
    return starts;
  }

  // Candidate j's file as drawn from d, measured there. A candidate drawn from nearer than its
  // own switch distance ships on a finer grid and with its lines' alpha for that distance
  // (draw_from): those files are kept by candidate, grid and scene, with the meter's key for each
  // (keys from 1000000 on, in the order they are first measured: deterministic).
  LevelMeter::Result measure(std::size_t j, double d) {
    if (d < cand_[j].switch_distance_m) {
      Candidate at = cand_[j];
      p_.draw_from(at, d);
      if (at.bits != cand_[j].bits || at.scene != cand_[j].scene) {
        auto [it, added] = nearer_files_.try_emplace({j, at.bits, at.scene});
        if (added) it->second = {next_key_++, p_.level_file(at)};
        return meter_.measure(it->second.first, it->second.second, d);
      }
    }
    if (files_[j].empty()) files_[j] = p_.level_file(cand_[j]);
    return meter_.measure(cand_[j].impostor ? -1 : int(cand_[j].source_level), files_[j], d);
  }

  // Whether candidate j has at most (1 - min_saving) x the primitives of candidate c.
  bool saves(std::size_t j, std::size_t c) const {
    return double(cand_[j].primitives) <= keep_at_most_ * double(cand_[c].primitives);
  }

  std::string saving_reason(std::size_t j, std::size_t c, double b) const {
    const double saved =
        cand_[c].primitives == 0 ? 0 : 1 - double(cand_[j].primitives) / double(cand_[c].primitives);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "saves %.3g of the primitives of %s (%llu -> %llu) at %s m, less than min_saving %.3g",
                  saved, level_name(cand_[c]).c_str(), static_cast<unsigned long long>(cand_[c].primitives),
                  static_cast<unsigned long long>(cand_[j].primitives), describe(b).c_str(),
                  options_.min_saving);
    return std::string(buf);
  }

  // Why a candidate is not kept: the latest decision about it, until its own band start has been
  // decided (what happened there is its reason).
  void note(std::size_t j, double b, std::string why) {
    if (settled_[j]) return;
    out_[j].reason = std::move(why);
    settled_[j] = b >= cand_[j].switch_distance_m;
  }

  // A kept level whose grid (for the distance it is drawn from) has more than
  // position_bits_min bits (the finest levels): the coarsest grid from position_bits_min bits on
  // whose file measures as passing at distance d (where the level is drawn from) is taken, with
  // that measurement; true when one is. Never coarser than position_bits_min, nor than the grid
  // the level's epsilon asks for at d.
  bool coarsest_grid(std::size_t j, double d) {
    Candidate& k = p_.candidates[j];
    if (k.impostor || std::none_of(k.fine.begin(), k.fine.end(), [](char f) { return f; })) return false;
    int finest = 0;  // bits of the finest grid among the fine meshes (16 for float positions)
    for (std::size_t m = 0; m < k.bits.size(); ++m)
      if (k.fine[m]) finest = std::max(finest, k.bits[m] == 0 ? 16 : k.bits[m]);
    for (int b = options_.position_bits_min; b < finest; ++b) {
      Candidate coarser = k;
      std::vector<int> bits = k.bits;
      for (std::size_t m = 0; m < bits.size(); ++m)
        if (k.fine[m] && (bits[m] == 0 || bits[m] > b)) bits[m] = b;
      p_.set_bits(coarser, std::move(bits));
      const int key = 1000 + 100 * int(k.source_level) + b;  // another file of the same level
      const LevelMeter::Result r = meter_.measure(key, p_.level_file(coarser), d);
      if (!r.error.passed) continue;
      k = std::move(coarser);
      out_[j].measured = r.error;
      return true;
    }
    return false;
  }

  // Candidate j at band start b: true, with its reason noted, when it saves too little over the
  // current level (it is not measured).
  bool too_little(std::size_t j, double b) {
    if (saves(j, c_)) return false;
    note(j, b, saving_reason(j, c_, b));
    return true;
  }

  // Candidate j's measurement when it passes at b, else nullopt with the failure noted.
  std::optional<MeasuredError> passes(std::size_t j, double b) {
    const LevelMeter::Result r = measure(j, b);
    if (r.error.passed) return r.error;
    note(j, b, "fails at " + describe(b) + " m: " + r.failure);
    return std::nullopt;
  }

  // Band start b: the impostor first (when it passes, no mesh level has fewer primitives); else
  // the band's own mesh level and the coarser ones, finest first, up to the first that fails;
  // else the levels between the current one and the band's own, coarsest first, up to the first
  // that passes; else the current level draws this band too.
  void decide_band(double b) {
    MeasuredError best_error;
    std::optional<std::size_t> best = has_impostor_ ? impostor_passes(b, best_error) : std::nullopt;
    // The band's own mesh level when it is coarser than the current one; the impostor's band has
    // none: the first level coarser than the current one.
    std::size_t from = c_ + 1;
    for (std::size_t j = c_ + 1; j < meshes_; ++j)
      if (cand_[j].switch_distance_m == b) from = j;
    if (!best) best = coarsest_passing_from(from, b, best_error);
    if (!best) best = nearest_passing_before(from, b, best_error);
    if (!best) return;
    LevelChoice& k = out_[*best];
    k.kept = true;
    k.switch_distance_m = b;
    k.measured = best_error;
    k.reason.clear();
    c_ = *best;
  }

  // The impostor when it saves enough and passes at b (its measurement in `error`), the mesh
  // levels after the current one noted as beaten by it.
  std::optional<std::size_t> impostor_passes(double b, MeasuredError& error) {
    const std::size_t imp = n_ - 1;
    const std::optional<MeasuredError> e = too_little(imp, b) ? std::nullopt : passes(imp, b);
    if (!e) return std::nullopt;
    error = *e;
    for (std::size_t j = c_ + 1; j < meshes_; ++j)
      note(j, b,
           "the impostor (" + std::to_string(cand_[imp].primitives) + " primitives) passes from " +
               describe(b) + " m");
    return imp;
  }

  // The mesh levels from `from` on, finest first, up to the first that fails: the coarsest of
  // those that pass (its measurement in `error`).
  std::optional<std::size_t> coarsest_passing_from(std::size_t from, double b, MeasuredError& error) {
    std::optional<std::size_t> mesh_best;
    for (std::size_t j = from; j < meshes_; ++j) {
      if (too_little(j, b)) continue;
      const std::optional<MeasuredError> e = passes(j, b);
      if (!e) {
        for (std::size_t k = j + 1; k < meshes_; ++k)
          note(k, b,
               "not measured at " + describe(b) + " m: level " + std::to_string(j) + ", finer, fails there");
        break;
      }
      // Passes; a coarser one may pass too.
      if (mesh_best)
        note(*mesh_best, b,
             "level " + std::to_string(j) + " (" + std::to_string(cand_[j].primitives) +
                 " primitives) passes at " + describe(b) + " m too");
      mesh_best = j;
      error = *e;
    }
    return mesh_best;
  }

  // The levels between the current one and `from`, coarsest first: the first that passes (its
  // measurement in `error`).
  std::optional<std::size_t> nearest_passing_before(std::size_t from, double b, MeasuredError& error) {
    for (std::size_t j = from; j-- > c_ + 1;) {
      if (too_little(j, b)) continue;
      if (const std::optional<MeasuredError> e = passes(j, b)) {
        error = *e;
        return j;
      }
    }
    return std::nullopt;
  }

  // An impostor that fails at its own distance (a far tree is a few dozen pixels, where one pixel
  // is 2 % of the check's footprint) is measured farther out, at b x 1.25^k, and kept from the
  // first of those distances where it passes: a chain with an impostor ends with it.
  void keep_impostor_farther() {
    const std::size_t imp = n_ - 1;
    if (!has_impostor_ || out_[imp].kept || cand_[c_].impostor || !saves(imp, c_)) return;
    double d = std::max(cand_[imp].switch_distance_m, out_[c_].switch_distance_m);
    for (int k = 0; k < kImpostorFartherSteps; ++k) {
      d *= kImpostorFartherFactor;
      const LevelMeter::Result r = measure(imp, d);
      if (!r.error.passed) continue;
      out_[imp].kept = true;
      out_[imp].switch_distance_m = d;
      out_[imp].measured = r.error;
      out_[imp].reason.clear();
      break;
    }
    if (!out_[imp].kept)
      out_[imp].reason = (out_[imp].reason.empty() ? std::string("fails") : out_[imp].reason) +
                         " (and at every distance up to " + describe(d) + " m)";
  }

  // A level kept from nearer than its own switch distance ships the grid and line alphas it was
  // measured with there (its measurement is that file's), then, as every kept level, the
  // coarsest grid search.
  void ship_kept_levels() {
    for (std::size_t j = 1; j < n_; ++j) {
      if (!out_[j].kept) continue;
      if (out_[j].switch_distance_m < cand_[j].switch_distance_m)
        p_.draw_from(p_.candidates[j], out_[j].switch_distance_m);
      coarsest_grid(j, out_[j].switch_distance_m);
    }
  }

  Prepared& p_;
  const PackOptions& options_;
  LevelMeter& meter_;
  const std::vector<Candidate>& cand_;  // p_.candidates
  const std::size_t n_;
  bool has_impostor_ = false;
  std::size_t meshes_ = 0;  // mesh candidates: those before the impostor
  double keep_at_most_ = 1;
  std::vector<LevelChoice> out_;
  std::size_t c_ = 0;  // the current level: the one kept last
  std::vector<char> settled_;
  std::vector<std::string> files_;  // each candidate's file, encoded once, as it is measured
  std::map<std::tuple<std::size_t, std::vector<int>, const gltf::Scene*>, std::pair<int, std::string>>
      nearer_files_;
  int next_key_ = 1000000;
};

}  // namespace

std::vector<LevelChoice> measured_choice(Prepared& p, const PackOptions& options, LevelMeter& meter) {
  return MeasuredChoice(p, options, meter).run();
}

}  // namespace sylva::pack
