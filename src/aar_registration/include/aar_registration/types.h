#pragma once

#include <Eigen/Core>

namespace aar_registration {

// Poses' 6-vectors and their covariances.
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

}  // namespace aar_registration
