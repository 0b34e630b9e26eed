#include "material/gaussian_sum_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>

#include "core/timer.h"

namespace sss {

double normalizedGaussian(double v, double r) {
  return std::exp(-r * r / (2.0 * v)) / (2.0 * M_PI * v);
}

double gaussianDiscIntegral(double v, double rho) {
  return -std::expm1(-rho * rho / (2.0 * v));
}

double gaussianCutoffRadius(double v, double tail) {
  return std::sqrt(-2.0 * v * std::log(tail));
}

glm::dvec3 GaussianSum::evaluate(double r) const {
  glm::dvec3 out(0.0);
  for (std::size_t k = 0; k < variances.size(); ++k)
    out += weights[k] * normalizedGaussian(variances[k], r);
  return out;
}

glm::dvec3 GaussianSum::totalReflectance() const {
  return std::accumulate(weights.begin(), weights.end(), glm::dvec3(0.0));
}

glm::dvec3 GaussianSum::integrateDisc(double rho) const {
  glm::dvec3 out(0.0);
  for (std::size_t k = 0; k < variances.size(); ++k)
    out += weights[k] * gaussianDiscIntegral(variances[k], rho);
  return out;
}

namespace {

constexpr int kGridPoints = 64;  // per channel, log-spaced
constexpr double kEnergyFraction = 0.999;
constexpr double kInnerRadius = 1e-3;  // grid starts at this fraction of r_999

// Per channel: samples y_i = sqrt(w_i) r_i R(r_i) with w_i the quadrature weight of int dr on a
// log grid (dr = r d ln r), so that sum y_i^2 = int (r R)^2 dr.
struct ChannelGrid {
  std::array<double, kGridPoints> r, scale, y;  // scale_i = sqrt(w_i) r_i
  double norm2 = 0.0;                           // sum y_i^2
  double innerEnergy = 0.0;                     // profile's disc integral up to r[0]
  double total = 0.0;                           // profile's total reflectance
};

double channelRadius(const DiffusionProfile& profile, int c, double fraction) {
  const double total = profile.totalReflectance()[c];
  double hi = 1e-3;
  while (profile.integrateDisc(hi)[c] < fraction * total && hi < 1e9) hi *= 2.0;
  double lo = 0.0;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (profile.integrateDisc(mid)[c] < fraction * total ? lo : hi) = mid;
  }
  return hi;
}

std::array<ChannelGrid, 3> sampleProfile(const DiffusionProfile& profile) {
  std::array<ChannelGrid, 3> grids;
  const glm::dvec3 total = profile.totalReflectance();
  for (int c = 0; c < 3; ++c) {
    ChannelGrid& g = grids[c];
    g.total = total[c];
    const double rHi = channelRadius(profile, c, kEnergyFraction);
    const double lnLo = std::log(rHi * kInnerRadius), lnHi = std::log(rHi);
    const double h = (lnHi - lnLo) / (kGridPoints - 1);
    for (int i = 0; i < kGridPoints; ++i) {
      const double r = std::exp(lnLo + i * h);
      const double w = r * h * ((i == 0 || i == kGridPoints - 1) ? 0.5 : 1.0);
      g.r[i] = r;
      g.scale[i] = std::sqrt(w) * r;
      g.y[i] = g.scale[i] * profile.evaluate(r)[c];
      g.norm2 += g.y[i] * g.y[i];
    }
    g.innerEnergy = profile.integrateDisc(g.r[0])[c];
  }
  return grids;
}

// Lawson-Hanson non-negative least squares on the normal equations (K is small).
std::vector<double> nnls(const std::vector<double>& ata, const std::vector<double>& atb, int K) {
  std::vector<double> x(K, 0.0), z(K);
  std::vector<char> passive(K, 0);
  double scale = 0.0;
  for (int k = 0; k < K; ++k) scale = std::max(scale, std::abs(atb[k]));
  const double eps = 1e-13 * std::max(scale, 1e-300);
  auto gradient = [&](int j) {
    double g = atb[j];
    for (int k = 0; k < K; ++k) g -= ata[j * K + k] * x[k];
    return g;
  };
  // Solves the passive subsystem into z (others 0) by Gaussian elimination with pivoting.
  auto solvePassive = [&]() {
    std::vector<int> idx;
    for (int k = 0; k < K; ++k)
      if (passive[k]) idx.push_back(k);
    const int n = static_cast<int>(idx.size());
    std::vector<double> m(n * (n + 1));
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) m[a * (n + 1) + b] = ata[idx[a] * K + idx[b]];
      m[a * (n + 1) + a] *= 1.0 + 1e-12;  // tiny ridge: nearly equal variances
      m[a * (n + 1) + n] = atb[idx[a]];
    }
    for (int col = 0; col < n; ++col) {
      int piv = col;
      for (int row = col + 1; row < n; ++row)
        if (std::abs(m[row * (n + 1) + col]) > std::abs(m[piv * (n + 1) + col])) piv = row;
      for (int b = 0; b <= n; ++b) std::swap(m[col * (n + 1) + b], m[piv * (n + 1) + b]);
      const double d = m[col * (n + 1) + col];
      if (d == 0.0) continue;
      for (int row = col + 1; row < n; ++row) {
        const double f = m[row * (n + 1) + col] / d;
        for (int b = col; b <= n; ++b) m[row * (n + 1) + b] -= f * m[col * (n + 1) + b];
      }
    }
    std::fill(z.begin(), z.end(), 0.0);
    for (int a = n - 1; a >= 0; --a) {
      double s = m[a * (n + 1) + n];
      for (int b = a + 1; b < n; ++b) s -= m[a * (n + 1) + b] * z[idx[b]];
      const double d = m[a * (n + 1) + a];
      z[idx[a]] = d != 0.0 ? s / d : 0.0;
    }
  };
  for (int outer = 0; outer < 3 * K; ++outer) {
    int best = -1;
    double bestG = eps;
    for (int j = 0; j < K; ++j) {
      if (passive[j]) continue;
      const double g = gradient(j);
      if (g > bestG) bestG = g, best = j;
    }
    if (best < 0) break;
    passive[best] = 1;
    for (int inner = 0; inner < 3 * K; ++inner) {
      solvePassive();
      bool feasible = true;
      double alpha = 1.0;
      for (int k = 0; k < K; ++k)
        if (passive[k] && z[k] <= 0.0) {
          feasible = false;
          alpha = std::min(alpha, x[k] / (x[k] - z[k]));
        }
      if (feasible) {
        x = z;
        break;
      }
      for (int k = 0; k < K; ++k) {
        if (!passive[k]) continue;
        x[k] += alpha * (z[k] - x[k]);
        if (x[k] <= 1e-300) passive[k] = 0, x[k] = 0.0;
      }
    }
  }
  return x;
}

struct Evaluation {
  std::vector<glm::dvec3> weights;
  glm::dvec3 channelError{0.0};
  glm::dvec3 totalErrorBeforeScaling{0.0};
  double error = 0.0;
};

// Weights for fixed variances: NNLS per channel, scaled so the sum of weights is the total.
Evaluation solveWeights(const std::array<ChannelGrid, 3>& grids,
                        const std::vector<double>& variances) {
  const int K = static_cast<int>(variances.size());
  Evaluation ev;
  ev.weights.assign(K, glm::dvec3(0.0));
  std::vector<double> a(kGridPoints * K), ata(K * K), atb(K);
  for (int c = 0; c < 3; ++c) {
    const ChannelGrid& g = grids[c];
    for (int i = 0; i < kGridPoints; ++i)
      for (int k = 0; k < K; ++k)
        a[i * K + k] = g.scale[i] * normalizedGaussian(variances[k], g.r[i]);
    for (int j = 0; j < K; ++j) {
      for (int k = j; k < K; ++k) {
        double s = 0.0;
        for (int i = 0; i < kGridPoints; ++i) s += a[i * K + j] * a[i * K + k];
        ata[j * K + k] = ata[k * K + j] = s;
      }
      double s = 0.0;
      for (int i = 0; i < kGridPoints; ++i) s += a[i * K + j] * g.y[i];
      atb[j] = s;
    }
    // One more row: the energy inside the grid's first radius, which the samples cannot see,
    // weighted so that a relative energy error e costs like a relative RMS error e. It keeps
    // narrow Gaussians from hiding energy at r ~ 0.
    if (g.total > 0.0) {
      const double w = std::sqrt(g.norm2) / g.total;
      for (int j = 0; j < K; ++j) {
        const double aj = w * gaussianDiscIntegral(variances[j], g.r[0]);
        for (int k = 0; k < K; ++k)
          ata[j * K + k] += aj * w * gaussianDiscIntegral(variances[k], g.r[0]);
        atb[j] += aj * w * g.innerEnergy;
      }
    }
    std::vector<double> x = nnls(ata, atb, K);
    const double sum = std::accumulate(x.begin(), x.end(), 0.0);
    ev.totalErrorBeforeScaling[c] = g.total > 0.0 ? sum / g.total - 1.0 : 0.0;
    const double factor = sum > 0.0 ? g.total / sum : 0.0;
    double err2 = 0.0;
    for (int i = 0; i < kGridPoints; ++i) {
      double s = 0.0;
      for (int k = 0; k < K; ++k) s += a[i * K + k] * x[k] * factor;
      err2 += (s - g.y[i]) * (s - g.y[i]);
    }
    for (int k = 0; k < K; ++k) ev.weights[k][c] = x[k] * factor;
    ev.channelError[c] = g.norm2 > 0.0 ? std::sqrt(err2 / g.norm2) : 0.0;
  }
  ev.error = std::max({ev.channelError.x, ev.channelError.y, ev.channelError.z});
  return ev;
}

// Nelder-Mead on f over R^n from x0 with initial step `step`, at most maxEvals evaluations.
std::vector<double> nelderMead(const std::function<double(const std::vector<double>&)>& f,
                               std::vector<double> x0, double step, int maxEvals, double target) {
  const int n = static_cast<int>(x0.size());
  std::vector<std::vector<double>> p(n + 1, x0);
  std::vector<double> fv(n + 1);
  for (int i = 0; i < n; ++i) p[i + 1][i] += step;
  int evals = 0;
  for (int i = 0; i <= n; ++i) fv[i] = f(p[i]), ++evals;
  std::vector<int> order(n + 1);
  while (evals < maxEvals) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fv[a] < fv[b]; });
    const int best = order[0], worst = order[n], second = order[n - 1];
    if (fv[best] <= target) break;
    std::vector<double> centroid(n, 0.0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) centroid[j] += p[order[i]][j] / n;
    auto along = [&](double t) {
      std::vector<double> q(n);
      for (int j = 0; j < n; ++j) q[j] = centroid[j] + t * (p[worst][j] - centroid[j]);
      return q;
    };
    std::vector<double> xr = along(-1.0);
    const double fr = f(xr);
    ++evals;
    if (fr < fv[best]) {
      std::vector<double> xe = along(-2.0);
      const double fe = f(xe);
      ++evals;
      if (fe < fr)
        p[worst] = xe, fv[worst] = fe;
      else
        p[worst] = xr, fv[worst] = fr;
    } else if (fr < fv[second]) {
      p[worst] = xr, fv[worst] = fr;
    } else {
      std::vector<double> xc = along(fr < fv[worst] ? -0.5 : 0.5);
      const double fc = f(xc);
      ++evals;
      if (fc < std::min(fr, fv[worst])) {
        p[worst] = xc, fv[worst] = fc;
      } else {
        for (int i = 1; i <= n; ++i) {
          for (int j = 0; j < n; ++j)
            p[order[i]][j] = p[best][j] + 0.5 * (p[order[i]][j] - p[best][j]);
          fv[order[i]] = f(p[order[i]]);
          ++evals;
        }
      }
    }
  }
  return p[std::min_element(fv.begin(), fv.end()) - fv.begin()];
}

// The search of fitGaussians: geometric ladders of K Gaussians (log-variances evenly spaced
// between two ends), then a free refinement, keeping the best fit seen.
class GaussianFitSearch {
 public:
  GaussianFitSearch(const DiffusionProfile& profile, double tolerance, int maxGaussians)
      : grids_(sampleProfile(profile)),
        tolerance_(tolerance),
        maxGaussians_(std::max(1, maxGaussians)),
        endsOf_(maxGaussians_ + 1),
        ladderError_(maxGaussians_ + 1, INFINITY) {
    // Variance range: a Gaussian's r G(r) peaks at sqrt(v) and holds 99.9% within 3.7 sqrt(v).
    double rMin = grids_[0].r.back(), rMax = 0.0, gridMin = grids_[0].r.front();
    for (const ChannelGrid& g : grids_) {
      rMin = std::min(rMin, g.r.back() * 1e-3);
      rMax = std::max(rMax, g.r.back());
      gridMin = std::min(gridMin, g.r.front());
    }
    lnVLo_ = 2.0 * std::log(rMin);
    lnVHi_ = 2.0 * std::log(rMax / 3.7);
    // Variances stay near where the metric sees them (the inner-energy row checks the rest).
    lnVMin_ = 2.0 * std::log(0.1 * gridMin);
    lnVMax_ = 2.0 * std::log(rMax);
    best_.profileName = profile.name();
    best_.tolerance = tolerance;
    best_.error = INFINITY;
  }

  // Fewest K whose ladder meets the tolerance: doubling, then bisection. Returns that K, or -1
  // when even maxGaussians does not meet it.
  int fewestLadder() {
    int lo = 0, hi = -1;
    for (int K = 1;; K = std::min(2 * K, maxGaussians_)) {
      if (fitLadder(K)) {
        hi = K;
        break;
      }
      lo = K;
      if (K == maxGaussians_) break;
    }
    while (hi > 0 && hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (fitLadder(mid) ? hi : lo) = mid;
    }
    return hi;
  }

  // Free refinement of every variance: one Gaussian fewer than the ladder needs (ladderK; or the
  // maximum when no ladder met the tolerance, ladderK < 0), when the ladder came close.
  void refine(int ladderK) {
    const int refineK = ladderK > 0 ? ladderK - 1 : maxGaussians_;
    if (refineK < 2) return;
    if (endsOf_[refineK].empty()) fitLadder(refineK);
    if (ladderError_[refineK] <= 2.0 * tolerance_ || ladderK < 0) {
      auto cost = [&](const std::vector<double>& x) { return evaluateLog(x).second.error; };
      const std::vector<double> refined =
          nelderMead(cost, ladder(endsOf_[refineK], refineK), 0.3, 25 * refineK + 20, tolerance_);
      keep(refined);
    }
  }

  GaussianSumFit& best() { return best_; }

 private:
  std::pair<std::vector<double>, Evaluation> evaluateLog(const std::vector<double>& lnV) const {
    std::vector<double> v(lnV.size());
    for (std::size_t k = 0; k < v.size(); ++k)
      v[k] = std::exp(std::clamp(lnV[k], lnVMin_, lnVMax_));
    std::sort(v.begin(), v.end());
    return std::make_pair(v, solveWeights(grids_, v));
  }

  // Best so far: the fewest Gaussians that meet the tolerance, else the lowest error.
  double keep(const std::vector<double>& lnV) {
    auto [variances, ev] = evaluateLog(lnV);
    const bool meets = ev.error <= tolerance_, bestMeets = best_.error <= tolerance_;
    const bool better = meets ? (!bestMeets || variances.size() < best_.sum.size() ||
                                 (variances.size() == best_.sum.size() && ev.error < best_.error))
                              : (!bestMeets && ev.error < best_.error);
    if (better) {
      best_.sum.variances = variances;
      best_.sum.weights = ev.weights;
      best_.error = ev.error;
      best_.channelError = ev.channelError;
      best_.totalErrorBeforeScaling = ev.totalErrorBeforeScaling;
    }
    return ev.error;
  }

  static std::vector<double> ladder(const std::vector<double>& e, int K) {
    std::vector<double> lnV(K);
    for (int k = 0; k < K; ++k)
      lnV[k] = K == 1 ? 0.5 * (e[0] + e[1]) : e[0] + (e[1] - e[0]) * k / (K - 1);
    return lnV;
  }

  // The best ladder of K Gaussians: Nelder-Mead on its two ends, warm-started from the nearest K
  // tried so far (the optimal ends move little with K). True when it meets the tolerance.
  bool fitLadder(int K) {
    std::vector<double> start = {lnVLo_ + 0.25 * (lnVHi_ - lnVLo_), lnVHi_};
    for (int d = 1; d <= maxGaussians_; ++d) {
      if (K - d >= 1 && !endsOf_[K - d].empty()) {
        start = endsOf_[K - d];
        break;
      }
      if (K + d <= maxGaussians_ && !endsOf_[K + d].empty()) {
        start = endsOf_[K + d];
        break;
      }
    }
    auto cost = [&](const std::vector<double>& e) {
      return evaluateLog(ladder(e, K)).second.error;
    };
    endsOf_[K] = nelderMead(cost, start, 1.0, K <= 3 ? 80 : 40, tolerance_);
    ladderError_[K] = keep(ladder(endsOf_[K], K));
    return ladderError_[K] <= tolerance_;
  }

  const std::array<ChannelGrid, 3> grids_;
  const double tolerance_;
  const int maxGaussians_;
  double lnVLo_ = 0.0, lnVHi_ = 0.0, lnVMin_ = 0.0, lnVMax_ = 0.0;
  std::vector<std::vector<double>> endsOf_;
  std::vector<double> ladderError_;
  GaussianSumFit best_;
};

// Drops Gaussians the NNLS switched off; merges equal variances (both clamped to a bound).
GaussianSum withoutUnusedGaussians(const GaussianSum& sum) {
  GaussianSum kept;
  for (std::size_t k = 0; k < sum.size(); ++k)
    if (!kept.variances.empty() && sum.variances[k] == kept.variances.back()) {
      kept.weights.back() += sum.weights[k];
    } else if (sum.weights[k].x > 0.0 || sum.weights[k].y > 0.0 || sum.weights[k].z > 0.0) {
      kept.variances.push_back(sum.variances[k]);
      kept.weights.push_back(sum.weights[k]);
    }
  return kept;
}

}  // namespace

glm::dvec3 gaussianSumError(const GaussianSum& sum, const DiffusionProfile& profile) {
  const std::array<ChannelGrid, 3> grids = sampleProfile(profile);
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    const ChannelGrid& g = grids[c];
    double err2 = 0.0;
    for (int i = 0; i < kGridPoints; ++i) {
      const double s = g.scale[i] * sum.evaluate(g.r[i])[c];
      err2 += (s - g.y[i]) * (s - g.y[i]);
    }
    out[c] = g.norm2 > 0.0 ? std::sqrt(err2 / g.norm2) : 0.0;
  }
  return out;
}

GaussianSumFit fitGaussians(const DiffusionProfile& profile, double tolerance, int maxGaussians) {
  Stopwatch watch;
  GaussianFitSearch search(profile, tolerance, maxGaussians);
  search.refine(search.fewestLadder());
  GaussianSumFit best = search.best();
  best.sum = withoutUnusedGaussians(best.sum);
  best.metTolerance = best.error <= tolerance;
  best.fitSeconds = watch.seconds();
  return best;
}

}  // namespace sss
