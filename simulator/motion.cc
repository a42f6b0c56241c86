#include "simulator/motion.h"

#include <array>
#include <cmath>

#include "geometry/se3.h"
#include "simulator/random_draws.h"

namespace slt {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A sin(2 pi t / period + phase).
struct Sinusoid {
  double amplitude = 0.0;
  double period = 1.0;
  double phase = 0.0;
  double At(double t) const { return amplitude * std::sin(2.0 * M_PI * t / period + phase); }
  // The same curve shifted to start at 0: At(t) - At(0).
  double FromZero(double t) const { return At(t) - At(0.0); }
};

// "paper" and "pure_rotation": body-frame increments cam_k_from_cam_{k-1} = Exp(xi_k) whose six
// components are sinusoids of k. The amplitudes of each triple are scaled to a root sum of
// squares equal to the bound, so |w_k| <= max rotation (the increment's angle) and |v_k| <= max
// translation (the increment's translation is J(w) v and |J(w) v| <= |v|).
void SinusoidMotion(const SinusoidMotionConfig& c, bool translate, RandomStream& rng, Trajectory* poses) {
  std::array<Sinusoid, 6> xi;
  for (Sinusoid& s : xi) {
    s.amplitude = Uniform(rng, 0.5, 1.0);
    s.period = Uniform(rng, c.period_min_frames, c.period_max_frames);
    s.phase = Uniform(rng, 0.0, 2.0 * M_PI);
  }
  // pure_rotation makes the same draws and drops the translation: with one seed it has the
  // rotation of the "paper" motion.
  const double bounds[2] = {translate ? c.max_translation_m : 0.0, c.max_rotation_deg * kDegToRad};
  for (int group = 0; group < 2; ++group) {
    const double norm = std::hypot(xi[3 * group].amplitude, xi[3 * group + 1].amplitude, xi[3 * group + 2].amplitude);
    for (int i = 0; i < 3; ++i) xi[3 * group + i].amplitude *= bounds[group] / norm;
  }
  for (std::size_t k = 1; k < poses->size(); ++k) {
    Vector6d twist;
    for (int i = 0; i < 6; ++i) twist[i] = xi[i].At(static_cast<double>(k));
    // world_from_cam_k = world_from_cam_{k-1} * cam_{k-1}_from_cam_k.
    (*poses)[k].world_from_cam = (*poses)[k - 1].world_from_cam * ExpSE3(twist).Inverse();
  }
}

// "loop": with s = 2 pi k / (frames - 1), the centre goes round the ellipse
// (rx (1 - cos s), wobble, rz sin s), yaw = A sin s; every term is periodic in s, so the last
// frame is the first pose again.
void LoopMotion(const LoopMotionConfig& c, RandomStream& rng, Trajectory* poses) {
  const double height_phase = Uniform(rng, 0.0, 2.0 * M_PI);
  const double pitch_phase = Uniform(rng, 0.0, 2.0 * M_PI);
  const double roll_phase = Uniform(rng, 0.0, 2.0 * M_PI);
  const double yaw_amplitude = c.yaw_amplitude_deg * kDegToRad, wobble = c.wobble_deg * kDegToRad;
  const double last = static_cast<double>(poses->size() - 1);
  for (std::size_t k = 1; k < poses->size(); ++k) {
    const double s = 2.0 * M_PI * static_cast<double>(k) / last;
    // Harmonics 2 and 3 of the loop: they close with it and are not in step with the turn.
    const double height = c.wobble_height_m * (std::sin(2.0 * s + height_phase) - std::sin(height_phase));
    const double pitch = wobble * (std::sin(2.0 * s + pitch_phase) - std::sin(pitch_phase));
    const double roll = wobble * (std::sin(3.0 * s + roll_phase) - std::sin(roll_phase));
    const double yaw = yaw_amplitude * std::sin(s);
    // Yaw about the (downward) y axis, positive to the right, then pitch and roll.
    const Eigen::Matrix3d rotation = ExpSO3(Eigen::Vector3d(0.0, yaw, 0.0)) * ExpSO3(Eigen::Vector3d(pitch, 0.0, 0.0)) *
                                     ExpSO3(Eigen::Vector3d(0.0, 0.0, roll));
    const Eigen::Vector3d centre(c.radius_x_m * (1.0 - std::cos(s)), -height, c.radius_z_m * std::sin(s));
    (*poses)[k].world_from_cam = Rigid3d(rotation, centre);
  }
}

// "forward": the centre moves step_m per frame along +z; the other translation components
// and the rotation vector wobble as sinusoids started at zero.
void ForwardMotion(const ForwardMotionConfig& c, RandomStream& rng, Trajectory* poses) {
  std::array<Sinusoid, 5> wobble;  // x, y, then the rotation vector
  for (std::size_t i = 0; i < wobble.size(); ++i) {
    wobble[i].amplitude = i < 2 ? c.wobble_m : c.wobble_deg * kDegToRad;
    wobble[i].period = c.wobble_period_frames * Uniform(rng, 0.5, 1.5);
    wobble[i].phase = Uniform(rng, 0.0, 2.0 * M_PI);
  }
  for (std::size_t k = 1; k < poses->size(); ++k) {
    const double t = static_cast<double>(k);
    const Eigen::Vector3d centre(wobble[0].FromZero(t), wobble[1].FromZero(t), c.step_m * t);
    const Eigen::Vector3d rotation(wobble[2].FromZero(t), wobble[3].FromZero(t), wobble[4].FromZero(t));
    (*poses)[k].world_from_cam = Rigid3d(ExpSO3(rotation), centre);
  }
}

}  // namespace

Trajectory MakeTrajectory(const MotionConfig& config, int frames, double frame_rate, std::uint64_t seed) {
  Trajectory poses(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) poses[k].time = k / frame_rate;
  RandomStream rng = MakeStream(seed, "motion");
  switch (config.type) {
    case MotionType::kPaper: SinusoidMotion(config.sinusoid, true, rng, &poses); break;
    case MotionType::kPureRotation: SinusoidMotion(config.sinusoid, false, rng, &poses); break;
    case MotionType::kLoop: LoopMotion(config.loop, rng, &poses); break;
    case MotionType::kForward: ForwardMotion(config.forward, rng, &poses); break;
    case MotionType::kStatic: break;
  }
  return poses;
}

}  // namespace slt
