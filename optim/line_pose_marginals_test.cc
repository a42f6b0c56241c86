#include "optim/line_pose_marginals.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace slt {
namespace {

// A bipartite information J^T J: every residual row sees one line (4 columns) and one pose (6),
// the lines first; each line seen by several poses, each pose by several lines.
struct Bipartite {
  Eigen::MatrixXd h;
  std::vector<Eigen::Matrix4d> a;
  Eigen::MatrixXd b;
  std::vector<Matrix6d> d;
};

Bipartite RandomBipartite(int lines, int poses, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  const int n = 4 * lines + 6 * poses;
  Bipartite x{Eigen::MatrixXd::Zero(n, n), std::vector<Eigen::Matrix4d>(lines, Eigen::Matrix4d::Zero()),
              Eigen::MatrixXd::Zero(4 * lines, 6 * poses), std::vector<Matrix6d>(poses, Matrix6d::Zero())};
  for (int k = 0; k < poses; ++k) {
    for (int i = 0; i < lines; ++i) {
      if ((i + k) % 3 == 0) continue;  // not every line in every pose: a sparse B
      Eigen::Matrix<double, 4, 10> j;  // two residuals in each of the two images
      for (int c = 0; c < j.size(); ++c) j(c) = normal(*rng);
      const Eigen::Matrix<double, 4, 4> j_line = j.leftCols<4>();
      const Eigen::Matrix<double, 4, 6> j_pose = j.rightCols<6>();
      x.a[i] += j_line.transpose() * j_line;
      x.d[k] += j_pose.transpose() * j_pose;
      x.b.block<4, 6>(4 * i, 6 * k) += j_line.transpose() * j_pose;
    }
  }
  for (int i = 0; i < lines; ++i) x.a[i] += Eigen::Matrix4d::Identity();  // the reference pair's view
  for (int i = 0; i < lines; ++i) x.h.block<4, 4>(4 * i, 4 * i) = x.a[i];
  for (int k = 0; k < poses; ++k) x.h.block<6, 6>(4 * lines + 6 * k, 4 * lines + 6 * k) = x.d[k];
  x.h.topRightCorner(4 * lines, 6 * poses) = x.b;
  x.h.bottomLeftCorner(6 * poses, 4 * lines) = x.b.transpose();
  return x;
}

TEST(LineMarginalCovariances, EqualTheLinesBlocksOfTheInverseInformation) {
  std::mt19937 rng(7);
  for (const auto& [lines, poses] : {std::pair{3, 2}, std::pair{12, 40}, std::pair{20, 150}}) {
    const Bipartite x = RandomBipartite(lines, poses, &rng);
    const Eigen::MatrixXd inverse = x.h.ldlt().solve(Eigen::MatrixXd::Identity(x.h.rows(), x.h.cols()));
    std::vector<Eigen::Matrix4d> covariances;
    ASSERT_TRUE(LineMarginalCovariances(x.a, x.b, x.d, &covariances));
    ASSERT_EQ(static_cast<int>(covariances.size()), lines);
    for (int i = 0; i < lines; ++i) {
      const Eigen::Matrix4d expected = inverse.block<4, 4>(4 * i, 4 * i);
      EXPECT_LT((covariances[i] - expected).norm(), 1e-9 * expected.norm()) << lines << " lines, " << poses << " poses, line " << i;
    }
  }
}

TEST(LineMarginalCovariances, GiveAPoseBlockOfTheInverseInformation) {
  std::mt19937 rng(10);
  const int lines = 12, poses = 40;
  const Bipartite x = RandomBipartite(lines, poses, &rng);
  const Eigen::MatrixXd inverse = x.h.ldlt().solve(Eigen::MatrixXd::Identity(x.h.rows(), x.h.cols()));
  std::vector<Eigen::Matrix4d> covariances;
  for (const int pose : {0, 17, poses - 1}) {
    Matrix6d pose_covariance = Matrix6d::Zero();
    ASSERT_TRUE(LineMarginalCovariances(x.a, x.b, x.d, &covariances, pose, &pose_covariance));
    const Matrix6d expected = inverse.block<6, 6>(4 * lines + 6 * pose, 4 * lines + 6 * pose);
    EXPECT_LT((pose_covariance - expected).norm(), 1e-9 * expected.norm()) << "pose " << pose;
    // More than the pose's own block alone gives (D_k^-1: the lines held fixed).
    const Eigen::SelfAdjointEigenSolver<Matrix6d> excess(pose_covariance - x.d[pose].inverse());
    EXPECT_GT(excess.eigenvalues().minCoeff(), -1e-12);
    EXPECT_GT(excess.eigenvalues().maxCoeff(), 1e-3 * expected.norm());
  }
}

TEST(LineMarginalCovariances, RefuseAnUndeterminedPose) {
  std::mt19937 rng(8);
  Bipartite x = RandomBipartite(4, 3, &rng);
  x.d[1].setZero();  // a pose no residual sees
  x.b.middleCols<6>(6).setZero();
  std::vector<Eigen::Matrix4d> covariances;
  EXPECT_FALSE(LineMarginalCovariances(x.a, x.b, x.d, &covariances));
}

TEST(LineMarginalCovariances, RefuseMismatchedSizes) {
  std::mt19937 rng(9);
  const Bipartite x = RandomBipartite(4, 3, &rng);
  std::vector<Eigen::Matrix4d> covariances;
  EXPECT_FALSE(LineMarginalCovariances(x.a, x.b.leftCols(12), x.d, &covariances));
}

}  // namespace
}  // namespace slt
