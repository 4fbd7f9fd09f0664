#include "aar_registration/imm.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <aar_geometry/pose.h>

namespace aar_registration {
namespace imm {
namespace {

Eigen::Vector3d Log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// P(switch from i to j within dt): leaving i at the rate 1 / sojourn_s, to the others equally.
double Transition(const std::vector<Model>& models, size_t i, size_t j, double dt) {
  const double stay = std::exp(-dt / models[i].sojourn_s);
  if (i == j) return stay;
  return (1.0 - stay) / static_cast<double>(models.size() - 1);
}

// The mixture of `models` weighted by `weights` around `reference`: its mean offset (the error
// state from the reference) and covariance.
void Moments(const std::vector<Model>& models, const std::vector<double>& weights,
             const Model& reference, Vector12d& mean, Matrix12d& covariance) {
  std::vector<Vector12d> d(models.size());
  mean.setZero();
  for (size_t i = 0; i < models.size(); ++i) {
    d[i] = Difference(models[i], reference);
    mean += weights[i] * d[i];
  }
  covariance.setZero();
  for (size_t i = 0; i < models.size(); ++i) {
    const Vector12d e = d[i] - mean;
    covariance += weights[i] * (models[i].P + e * e.transpose());
  }
}

}  // namespace

Vector12d Difference(const Model& model, const Model& reference) {
  Vector12d d;
  d << model.p - reference.p, Log(model.R * reference.R.transpose()), model.v - reference.v,
      model.w - reference.w;
  return d;
}

void Apply(const Vector12d& d, Model& model) {
  model.p += d.segment<3>(0);
  model.R = Eigen::Quaterniond(aar_geometry::RotationExp(d.segment<3>(3)) * model.R)
                .normalized()
                .toRotationMatrix();
  model.v += d.segment<3>(6);
  model.w += d.segment<3>(9);
}

void Mix(double dt, std::vector<Model>& models) {
  const size_t n = models.size();
  if (n < 2 || !(dt > 0.0)) return;
  std::vector<Model> mixed = models;
  for (size_t j = 0; j < n; ++j) {
    std::vector<double> weights(n);
    double predicted = 0.0;
    for (size_t i = 0; i < n; ++i) {
      weights[i] = Transition(models, i, j, dt) * models[i].probability;
      predicted += weights[i];
    }
    if (!(predicted > 0.0)) continue;
    for (double& w : weights) w /= predicted;
    Vector12d mean;
    Moments(models, weights, models[j], mean, mixed[j].P);
    Apply(mean, mixed[j]);
    mixed[j].probability = predicted;
  }
  models = mixed;
}

Model Combine(const std::vector<Model>& models) {
  if (models.size() == 1) return models.front();
  const auto best = std::max_element(
      models.begin(), models.end(),
      [](const Model& a, const Model& b) { return a.probability < b.probability; });
  Model out = *best;
  std::vector<double> weights;
  for (const Model& m : models) weights.push_back(m.probability);
  Vector12d mean;
  Moments(models, weights, *best, mean, out.P);
  Apply(mean, out);
  out.probability = 1.0;
  return out;
}

void Weigh(const std::vector<double>& log_likelihoods, std::vector<Model>& models) {
  if (models.size() < 2 || log_likelihoods.size() != models.size()) return;
  double top = -std::numeric_limits<double>::infinity();
  for (double l : log_likelihoods)
    if (std::isfinite(l)) top = std::max(top, l);
  if (!std::isfinite(top)) return;
  std::vector<double> weights(models.size(), 0.0);
  double sum = 0.0;
  for (size_t i = 0; i < models.size(); ++i) {
    if (std::isfinite(log_likelihoods[i]))
      weights[i] = models[i].probability * std::exp(log_likelihoods[i] - top);
    sum += weights[i];
  }
  if (!(sum > 0.0) || !std::isfinite(sum)) return;
  for (size_t i = 0; i < models.size(); ++i) models[i].probability = weights[i] / sum;
}

}  // namespace imm
}  // namespace aar_registration
