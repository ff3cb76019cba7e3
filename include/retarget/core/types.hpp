#pragma once
/// Eigen aliases used across the project. Frames and units are carried by variable names
/// (`p_W_com` is a position in the world frame, `X_W_foot` a pose of the foot in the world frame);
/// these aliases only fix the scalar type (double everywhere).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rt {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using VecX = Eigen::VectorXd;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using MatX = Eigen::MatrixXd;
using Mat3X = Eigen::Matrix3Xd;
using Matrix6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;
/// Row-major dynamic matrix: the layout MuJoCo uses for Jacobians and the mass matrix.
using MatXr = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Quat = Eigen::Quaterniond;
using Iso3 = Eigen::Isometry3d;
using AngleAxis = Eigen::AngleAxisd;

using VecXRef = Eigen::Ref<VecX>;
using VecXCRef = Eigen::Ref<const VecX>;

}  // namespace rt
