#include "methods/stereo_ekf/pose_velocity_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "geometry/se3.h"

namespace slt {
namespace {

using Matrix12d = PoseVelocityFilter::Matrix12d;

StereoEkfOptions Options(FilterState state) {
  StereoEkfOptions o;
  o.state = state;
  return o;
}

// Q of eq. 18: the per-frame velocity change.
Matrix6d VelocityNoise(const StereoEkfOptions& o) {
  Vector6d q;
  q << Eigen::Vector3d::Constant(o.accel_sigma_m * o.accel_sigma_m),
      Eigen::Vector3d::Constant(o.accel_sigma_rad * o.accel_sigma_rad);
  return q.asDiagonal();
}

// A filter started and corrected once by `delta` with posterior pose covariance `shrink` P_pp:
// moving, with pose and velocity correlated.
PoseVelocityFilter Moving(const StereoEkfOptions& o, const Vector6d& delta, double shrink) {
  PoseVelocityFilter f;
  f.Reset(o);
  f.Predict();
  const Matrix6d p_pp = f.PoseCovariance();
  f.Correct(delta, shrink * p_pp, p_pp.inverse());
  return f;
}

// A per-frame motion.
Vector6d SomeDelta() { return (Vector6d() << 0.008, -0.004, 0.01, 0.012, -0.006, 0.009).finished(); }

TEST(PoseVelocityFilter, ProcessNoiseScaleMultipliesQUntilReset) {
  // From rest (xi = 0) the velocity block after one prediction is the prior plus q^2 Q.
  const StereoEkfOptions o = Options(FilterState::kPoseVelocity);
  PoseVelocityFilter f;
  f.Reset(o);
  f.SetProcessNoiseScale(0.25);
  f.Predict();
  PoseVelocityFilter unscaled;
  unscaled.Reset(o);
  unscaled.Predict();
  const Matrix6d added = f.covariance().bottomRightCorner<6, 6>() - unscaled.covariance().bottomRightCorner<6, 6>();
  EXPECT_LT((added - (0.25 - 1.0) * VelocityNoise(o)).norm(), 1e-15);
  f.Reset(o);
  EXPECT_EQ(f.process_noise_scale_sq(), 1.0);
}

TEST(PoseVelocityFilter, FirstPredictionFromRestIsThePriorPlusQ) {
  // At rest (xi = 0) F = [[I, I], [0, I]]: the pose inherits the velocity's uncertainty.
  for (const FilterState state : {FilterState::kVelocity, FilterState::kPoseVelocity}) {
    const StereoEkfOptions o = Options(state);
    PoseVelocityFilter f;
    f.Reset(o);
    f.Predict();
    const double vm = o.initial_velocity_sigma_m * o.initial_velocity_sigma_m + o.accel_sigma_m * o.accel_sigma_m;
    const double vr =
        o.initial_velocity_sigma_rad * o.initial_velocity_sigma_rad + o.accel_sigma_rad * o.accel_sigma_rad;
    Vector6d diag;
    diag << vm, vm, vm, vr, vr, vr;
    const Matrix6d d = diag.asDiagonal();
    EXPECT_LT((f.covariance().topLeftCorner<6, 6>() - d).norm(), 1e-15) << StereoEkfOptionsToJson(o)["state"];
    EXPECT_LT((f.covariance().topRightCorner<6, 6>() - d).norm(), 1e-15) << StereoEkfOptionsToJson(o)["state"];
    EXPECT_LT((f.covariance().bottomRightCorner<6, 6>() - d).norm(), 1e-15) << StereoEkfOptionsToJson(o)["state"];
    EXPECT_DOUBLE_EQ(vm, 0.02 * 0.02 + 0.002 * 0.002);  // the defaults, written out
    EXPECT_TRUE(f.cam_from_ref().translation.isZero());
  }
}

// Error state e = [d; dv] (true M = Exp(d) M, true xi = xi + dv); the motion M' = Exp(xi) M maps
// it to d' = Log(Exp(xi + dv) Exp(d) M (Exp(xi) M)^-1). Its Jacobian at e = 0, by central
// differences, is the F the filter propagates with.
Eigen::Matrix<double, 6, 12> NumericTransition(const Rigid3d& m, const Vector6d& xi) {
  const Rigid3d predicted_inverse = (ExpSE3(xi) * m).Inverse();
  Eigen::Matrix<double, 6, 12> f;
  const double h = 1e-6;
  for (int j = 0; j < 12; ++j) {
    Vector6d d = Vector6d::Zero(), dv = Vector6d::Zero();
    (j < 6 ? d(j) : dv(j - 6)) = h;
    const Vector6d plus = LogSE3(ExpSE3(xi + dv) * ExpSE3(d) * m * predicted_inverse);
    const Vector6d minus = LogSE3(ExpSE3(xi - dv) * ExpSE3(-d) * m * predicted_inverse);
    f.col(j) = (plus - minus) / (2 * h);
  }
  return f;
}

TEST(PoseVelocityFilter, PredictionPropagatesWithTheMotionModelsJacobian) {
  // Bring the filter to a moving state with a full covariance (a correction couples pose and
  // velocity), then compare its prediction with F (P + diag(0, Q)) F^T (eq. 18), F taken
  // numerically from the motion model.
  const StereoEkfOptions o = Options(FilterState::kPoseVelocity);
  PoseVelocityFilter f = Moving(o, SomeDelta(), 0.3);
  ASSERT_GT(f.velocity().norm(), 1e-3);
  const Rigid3d m = f.cam_from_ref();
  const Vector6d xi = f.velocity();
  Matrix12d p = f.covariance();
  p.bottomRightCorner<6, 6>() += VelocityNoise(o);
  Matrix12d big_f = Matrix12d::Identity();
  big_f.topRows<6>() = NumericTransition(m, xi);
  const Matrix12d expected = big_f * p * big_f.transpose();

  f.Predict();
  EXPECT_LT((LogSE3(f.cam_from_ref() * (ExpSE3(xi) * m).Inverse())).norm(), 1e-12);
  // The filter uses J_l to first order: agreement to O(|xi|^2) relative.
  EXPECT_LT((f.covariance() - expected).norm(), 1e-3 * expected.norm());
  // A wrong convention (e.g. a right instead of a left perturbation) breaks it at O(|xi|).
  Matrix12d wrong_f = Matrix12d::Identity();
  wrong_f.topLeftCorner<6, 6>() = Adjoint(ExpSE3(xi)).inverse();
  wrong_f.topRightCorner<6, 6>() = Matrix6d::Identity();
  EXPECT_GT((wrong_f * p * wrong_f.transpose() - expected).norm(), 1e-2 * expected.norm());
}

TEST(PoseVelocityFilter, CorrectionIsTheKalmanUpdateOfTheFullState) {
  // Measuring the pose (H = [I 0]) with covariance R: the filter's split update (pose MAP by the
  // caller, velocity by the Gaussian conditional) equals the 12-D Kalman update.
  const StereoEkfOptions o = Options(FilterState::kPoseVelocity);
  PoseVelocityFilter f = Moving(o, (Vector6d() << 0.006, 0.002, -0.004, 0.01, 0.003, -0.007).finished(), 0.5);
  f.Predict();  // a prior with pose-velocity correlation

  const Matrix12d p = f.covariance();
  const Vector6d velocity_before = f.velocity();
  const Rigid3d pose_before = f.cam_from_ref();
  Vector6d r_diag;
  r_diag << 1e-6, 2e-6, 1.5e-6, 4e-6, 3e-6, 5e-6;
  const Matrix6d r = r_diag.asDiagonal();
  Vector6d z;  // innovation of the pose measurement
  z << 0.001, -0.002, 0.0015, 0.003, -0.001, 0.002;
  Eigen::Matrix<double, 6, 12> h = Eigen::Matrix<double, 6, 12>::Zero();
  h.leftCols<6>().setIdentity();
  const Eigen::Matrix<double, 12, 6> k = p * h.transpose() * (h * p * h.transpose() + r).inverse();
  const Eigen::Matrix<double, 12, 1> correction = k * z;
  const Matrix12d expected = (Matrix12d::Identity() - k * h) * p;

  const Matrix6d p_pp = p.topLeftCorner<6, 6>();
  const Matrix6d posterior = (p_pp.inverse() + r.inverse()).inverse();
  f.Correct(correction.head<6>(), posterior, p_pp.inverse());
  EXPECT_LT((f.velocity() - velocity_before - correction.tail<6>()).norm(), 1e-9 * correction.norm());
  EXPECT_LT((LogSE3(f.cam_from_ref() * pose_before.Inverse()) - correction.head<6>()).norm(), 1e-12);
  EXPECT_LT((f.covariance() - 0.5 * (expected + expected.transpose())).norm(), 1e-9 * p.norm());
}

TEST(PoseVelocityFilter, VelocityStateForgetsThePoseUncertainty) {
  // The paper's filter (eq. 10): before each prediction M_{t-1} is exact, so the predicted pose
  // covariance is the velocity's, carried through J_l, whatever the pose covariance was.
  const StereoEkfOptions o = Options(FilterState::kVelocity);
  PoseVelocityFilter f = Moving(o, SomeDelta(), 0.3);
  const Matrix6d p_vv = f.covariance().bottomRightCorner<6, 6>() + VelocityNoise(o);
  const Matrix6d jl = LeftJacobianSE3FirstOrder(f.velocity());
  f.Predict();
  EXPECT_LT((f.PoseCovariance() - jl * p_vv * jl.transpose()).norm(), 1e-12 * p_vv.norm());
}

TEST(PoseVelocityFilter, MovedCovarianceReplacesThePoseBlockAndScalesItsCorrelation) {
  const StereoEkfOptions o = Options(FilterState::kPoseVelocity);
  PoseVelocityFilter f = Moving(o, SomeDelta(), 0.3);
  f.Predict();
  const Matrix12d before = f.covariance();
  const Matrix6d p_pp = before.topLeftCorner<6, 6>();
  ASSERT_GT((before.topRightCorner<6, 6>().norm()), 0.0);  // pose and velocity correlated
  // A smoother's marginal: another positive-definite matrix, larger in some directions and
  // smaller in others.
  Matrix6d target = p_pp;
  target(0, 0) *= 4.0;
  target(5, 5) *= 0.25;
  target(1, 3) = target(3, 1) = 0.3 * std::sqrt(target(1, 1) * target(3, 3));
  const Rigid3d moved = ExpSE3(SomeDelta()) * f.cam_from_ref();
  const Matrix6d t = f.MovePose(moved, target);
  EXPECT_LT(LogSE3(f.cam_from_ref() * moved.Inverse()).norm(), 1e-15);
  const Matrix12d after = f.covariance();
  EXPECT_LT((after.topLeftCorner<6, 6>() - target).norm(), 1e-12 * target.norm());
  EXPECT_LT((t * p_pp * t.transpose() - target).norm(), 1e-9 * target.norm());
  EXPECT_LT((after.topRightCorner<6, 6>() - t * before.topRightCorner<6, 6>()).norm(), 1e-15);
  EXPECT_TRUE((after.bottomRightCorner<6, 6>() == before.bottomRightCorner<6, 6>()));
  EXPECT_TRUE((after.bottomLeftCorner<6, 6>() == after.topRightCorner<6, 6>().transpose()));
  // Still a covariance: the map of the pose error keeps the joint matrix positive semi-definite.
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix12d>(after).eigenvalues().minCoeff(), -1e-12 * after.norm());

  // With no pose uncertainty yet (just after a new reference pair), the pose error is replaced,
  // not mapped: uncorrelated with the velocity.
  PoseVelocityFilter fresh = Moving(o, SomeDelta(), 0.3);
  fresh.StartNewReferencePair();
  ASSERT_TRUE(fresh.PoseCovariance() == Matrix6d::Zero());
  EXPECT_TRUE(fresh.MovePose(fresh.cam_from_ref(), target) == Matrix6d::Zero());
  EXPECT_LT((fresh.PoseCovariance() - target).norm(), 1e-12 * target.norm());
  EXPECT_TRUE((fresh.covariance().topRightCorner<6, 6>() == Matrix6d::Zero()));
}

}  // namespace
}  // namespace slt
