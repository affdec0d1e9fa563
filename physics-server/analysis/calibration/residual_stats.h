// Statistics of a calibration residual: the cross-validation split into time
// blocks, the error (NRMSE), its structured part (the gap), the whiteness
// ratio, and 95 % intervals from a Jacobian with the covariance inflated by
// the residual's correlation length. docs/calibration.md, "Method".
#pragma once

#include <Eigen/Dense>

#include <cstddef>
#include <utility>
#include <vector>

namespace chainsim {

constexpr int kCvBlocks = 8;   // time blocks; even = training, odd = held out
constexpr int kBatchesPerBlock = 5;   // equal time spans of a block (the held-out test's batches)

// which samples a statistic is taken over
enum class Samples { training = 0, held_out = 1, all = 2 };

// the block of each sample: kCvBlocks equal spans of time from t.front();
// batch: the sample's span within its block (kBatchesPerBlock per block)
struct BlockSplit {
  std::vector<int> block, batch;
  bool in(size_t k, Samples s) const {
    return s == Samples::all || (block[k] % 2) == static_cast<int>(s);
  }
};
BlockSplit split_blocks(const std::vector<double>& t, int blocks = kCvBlocks);

// model - measured per sample, each channel divided by its scale (the std of
// the measured channel); current is all 0 when not measured
struct Residual {
  std::vector<double> angle, current;
  bool has_current = false;
  bool finite = true;
  size_t size() const { return angle.size(); }
  int channels() const { return has_current ? 2 : 1; }
  // the squared residual of sample k, summed over the channels
  double energy(size_t k) const {
    return angle[k] * angle[k] + (has_current ? current[k] * current[k] : 0.0);
  }
};

// the white (sample-to-sample) noise of a residual per channel, in its
// units: sqrt(half the mean square of first differences within blocks), on
// all samples; what the fit's loss divides by
struct NoiseScale {
  double angle = 1, current = 1;
};
NoiseScale white_noise_scale(const Residual& r, const BlockSplit& s);

// per sample, the squared residual in noise units summed over the channels
// (the Gaussian log-likelihood's -2x, up to a constant); 1e12 when non-finite
std::vector<double> sample_loss(const Residual& r, const NoiseScale& n);

// lag-1 autocorrelation of the residual in noise units on `set` (pairs
// within blocks, the channels pooled), clamped to [0, 0.999]
double residual_rho(const Residual& r, const NoiseScale& n, const BlockSplit& s, Samples set);

// population standard deviation
double stdev(const std::vector<double>& v);

// sqrt of the mean over channels of the mean squared residual on `set`
// (samples with (*mask)[k] only, when given); 1e6 for a non-finite residual
double nrmse(const Residual& r, const BlockSplit& s, Samples set, const std::vector<bool>* mask = nullptr);

// rms / (rms of first differences / sqrt 2), differences within blocks, the
// larger of the channels: ~1 for white noise, >> 1 for a slow (structured)
// residual
double whiteness(const Residual& r, const BlockSplit& s, Samples set);

// the gap: per channel sqrt(max(0, MS - MS_white)), MS_white = half the mean
// square of first differences (within blocks), combined like nrmse: the
// error left once white measurement noise is taken out; 1e6 when non-finite
double structured_error(const Residual& r, const BlockSplit& s, Samples set);

// the gaps of two models of one measurement (a, b) against one white level:
// per channel the smaller of the two residuals' MS_white on `set`. The
// measurement's noise is in both residuals, and a model's misfit can only
// add to its residual's first differences (a misfit that changes from one
// sample to the next, a backlash's at a low sample rate, would otherwise be
// counted as that model's noise and leave it a smaller gap than a model
// without the misfit)
std::pair<double, double> structured_errors(const Residual& a, const Residual& b, const BlockSplit& s, Samples set);

// 95 % intervals of the parameters x from the residual's Jacobian J (rows:
// the angle residuals of `samples` samples, then the current's if any) and
// the residual r at x: Gauss-Newton covariance s2 (J'J)^-1, inflated by
// (1 + rho) / (1 - rho), rho = lag-1 autocorrelation of the angle residual.
// Lower bounds of x[first_nonnegative..] are floored at 0.
std::vector<std::pair<double, double>> confidence_intervals(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                                                            size_t samples, const std::vector<double>& x,
                                                            size_t first_nonnegative);

}  // namespace chainsim
