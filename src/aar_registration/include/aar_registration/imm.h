#pragma once

// The interacting-multiple-model arithmetic of the Tracker (tracker.h): each model is a
// constant-velocity filter over SE(3) with its own process noise; the models are mixed before
// each prediction by a Markov chain over their probabilities and combined (moment-matched) for
// the output. Error states are [dp, dtheta, dv, dw] with dtheta left-multiplied, as Tracker's.
// References: Bar-Shalom, Li and Kirubarajan, "Estimation with Applications to Tracking and
// Navigation" (2001), 11.6; the mixing on the rotation is done in the tangent space at the
// model it mixes into.

#include <vector>

#include <Eigen/Core>

#include "aar_registration/types.h"

namespace aar_registration {
namespace imm {

using Matrix12d = Eigen::Matrix<double, 12, 12>;
using Vector12d = Eigen::Matrix<double, 12, 1>;

struct Model {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // [m] receiver origin, tanker frame
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // [m/s] tanker frame
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  // [rad/s] tanker frame
  Matrix12d P = Matrix12d::Zero();              // error state: dp, dtheta, dv, dw
  double probability = 1.0;
  double acceleration_sigma = 0.0;          // [m/s^2] its white acceleration
  double angular_acceleration_sigma = 0.0;  // [rad/s^2]
  double sojourn_s = 0.0;                   // [s] mean time in it before a switch
};

// The error state that takes `reference` to `model`.
Vector12d Difference(const Model& model, const Model& reference);
// `model` moved by the error state `d`.
void Apply(const Vector12d& d, Model& model);

// Mixes the models for a step of `dt` seconds: each model starts from the mixture of all,
// weighted by the chance that the receiver was in each and is now in it (switches leave a model
// at the rate 1 / sojourn_s), and its probability becomes the predicted one. One model: no-op.
void Mix(double dt, std::vector<Model>& models);

// The moment-matched mixture of the models (state at the most probable one, covariance with
// the spread of the means); the model itself if there is only one.
Model Combine(const std::vector<Model>& models);

// Each model's probability times exp(log_likelihood), normalised. Unchanged if every
// likelihood underflows or is not finite.
void Weigh(const std::vector<double>& log_likelihoods, std::vector<Model>& models);

}  // namespace imm
}  // namespace aar_registration
