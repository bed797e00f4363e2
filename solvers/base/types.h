#pragma once
//! Matrix aliases shared by every layer, so algorithms never spell out Eigen types twice.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products are everywhere; without it they compile but fail to link
#include <Eigen/SparseCore>

namespace db {

using Index = int;  // CHOLMOD's int interface and Eigen's default StorageIndex agree on 32-bit indices.

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
//! #V by 3 vertex positions.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
//! #F by 3 triangle corner indices.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using DenseMat = Eigen::MatrixXd;
using DenseVec = Eigen::VectorXd;
//! Compressed sparse column, 32-bit indices (what CHOLMOD's int API takes without copying).
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

}  // namespace db
