#include "simulator/motion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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


// The attitude of a camera whose horizontal heading is `yaw` (about the downward y axis,
// positive to the right), tilted by `pitch` (about its x axis, positive up) and `roll` (about its
// z axis, positive right side down): world_from_cam's rotation.
Eigen::Matrix3d Attitude(double yaw, double pitch, double roll) {
  return ExpSO3(Eigen::Vector3d(0.0, yaw, 0.0)) * ExpSO3(Eigen::Vector3d(pitch, 0.0, 0.0)) *
         ExpSO3(Eigen::Vector3d(0.0, 0.0, roll));
}
// Unit heading and right vector of a horizontal yaw.
Eigen::Vector3d Heading(double yaw) { return {std::sin(yaw), 0.0, std::cos(yaw)}; }
Eigen::Vector3d RightOf(double yaw) { return {std::cos(yaw), 0.0, -std::sin(yaw)}; }
constexpr double kGravity = 9.81;

// Sinusoids of time (seconds) with periods drawn in [period_min, period_max], phases in
// [0, 2 pi) and relative amplitudes in [0.5, 1] times `weight`.
std::vector<Sinusoid> DrawSway(RandomStream& rng, int count, double weight, double period_min, double period_max) {
  std::vector<Sinusoid> sway(static_cast<std::size_t>(count));
  for (Sinusoid& s : sway) {
    s.amplitude = weight * Uniform(rng, 0.5, 1.0);
    s.period = Uniform(rng, period_min, period_max);
    s.phase = Uniform(rng, 0.0, 2.0 * M_PI);
  }
  return sway;
}
double SumFromZero(const std::vector<Sinusoid>& sway, double t) {
  double sum = 0.0;
  for (const Sinusoid& s : sway) sum += s.FromZero(t);
  return sum;
}
// Scales the groups' amplitudes so that the root mean square rate of their sum is `rms_rate`:
// a sinusoid A sin(2 pi t / P + phase) has the mean square rate (2 pi A / P)^2 / 2.
void ScaleToRmsRate(std::vector<std::vector<Sinusoid>*> groups, double rms_rate) {
  double mean_square = 0.0;
  for (const std::vector<Sinusoid>* group : groups) {
    for (const Sinusoid& s : *group) mean_square += 0.5 * std::pow(2.0 * M_PI * s.amplitude / s.period, 2);
  }
  const double scale = mean_square > 0.0 ? rms_rate / std::sqrt(mean_square) : 0.0;
  for (std::vector<Sinusoid>* group : groups) {
    for (Sinusoid& s : *group) s.amplitude *= scale;
  }
}

// Profile "handheld": the centre (x, y, z) and the yaw, pitch and roll sway as sums of two slow
// sinusoids each, started at zero (the vertical and the roll with smaller weights).
void HandheldMotion(const HandheldMotionConfig& c, RandomStream& rng, Trajectory* poses) {
  std::array<std::vector<Sinusoid>, 6> sway;
  const double weights[6] = {1.0, 0.4, 1.0, 1.0, 0.6, 0.3};  // x, y, z, yaw, pitch, roll
  for (int i = 0; i < 6; ++i) sway[i] = DrawSway(rng, 2, weights[i], c.period_min_s, c.period_max_s);
  ScaleToRmsRate({&sway[0], &sway[1], &sway[2]}, c.speed_mps);
  ScaleToRmsRate({&sway[3], &sway[4], &sway[5]}, c.rate_dps * kDegToRad);
  for (std::size_t k = 1; k < poses->size(); ++k) {
    const double t = (*poses)[k].time;
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = SumFromZero(sway[i], t);
    (*poses)[k].world_from_cam = Rigid3d(Attitude(v[3], v[4], v[5]), Eigen::Vector3d(v[0], v[1], v[2]));
  }
}

// A minimum-jerk move over [0, 1]: s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5, its peak rate is
// 1.875 (Flash & Hogan 1985); and its second derivative.
double MinimumJerk(double tau) { return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau)); }
double MinimumJerkAcceleration(double tau) { return 60.0 * tau - 180.0 * tau * tau + 120.0 * tau * tau * tau; }
constexpr double kMinimumJerkPeakRate = 1.875;

// Profile "mav": a sequence of manoeuvres from hover at the start pose.
void MavMotion(const MavMotionConfig& c, RandomStream& rng, Trajectory* poses) {
  struct Manoeuvre {
    double start_s, duration_s;
    Eigen::Vector3d from, to;  // centre
    double yaw_from, yaw_to;
  };
  const double end_s = poses->back().time;
  std::vector<Manoeuvre> plan;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double yaw = 0.0, t = 0.0;
  const double max_turn = c.max_turn_deg * kDegToRad, max_yaw_rate = c.max_yaw_rate_dps * kDegToRad;
  while (t <= end_s) {
    Manoeuvre m{t, c.min_segment_s * Uniform(rng, 1.0, 2.0), centre, centre, yaw, yaw};
    if (Uniform01(rng) >= c.hover_probability) {
      const bool move = Uniform01(rng) < 0.7, turn = Uniform01(rng) < 0.7;
      if (move || !turn) {
        for (int i = 0; i < 3; ++i) m.to[i] = Uniform(rng, -c.extent_m[i], c.extent_m[i]);
      }
      if (turn) m.yaw_to = yaw + Uniform(rng, -max_turn, max_turn);
      m.duration_s = std::max({c.min_segment_s, kMinimumJerkPeakRate * (m.to - m.from).norm() / c.max_speed_mps,
                               kMinimumJerkPeakRate * std::abs(m.yaw_to - m.yaw_from) / max_yaw_rate});
    }
    plan.push_back(m);
    centre = m.to;
    yaw = m.yaw_to;
    t += m.duration_s;
  }
  std::array<std::vector<Sinusoid>, 5> jitter;  // x, y, z, pitch, roll
  for (int i = 0; i < 5; ++i) {
    jitter[i] = DrawSway(rng, 2, 0.5 * (i < 3 ? c.hover_jitter_m : c.hover_jitter_deg * kDegToRad), 0.3, 1.5);
  }
  std::size_t current = 0;
  for (std::size_t k = 1; k < poses->size(); ++k) {
    const double time = (*poses)[k].time;
    while (current + 1 < plan.size() && plan[current + 1].start_s <= time) ++current;
    const Manoeuvre& m = plan[current];
    const double tau = std::clamp((time - m.start_s) / m.duration_s, 0.0, 1.0);
    const Eigen::Vector3d move = m.to - m.from;
    const double heading = m.yaw_from + MinimumJerk(tau) * (m.yaw_to - m.yaw_from);
    // A quadrotor tilts into its horizontal acceleration: forward tips the nose down, to the
    // right lowers the right side.
    const Eigen::Vector3d acceleration = MinimumJerkAcceleration(tau) / (m.duration_s * m.duration_s) * move;
    const double pitch = -acceleration.dot(Heading(heading)) / kGravity + SumFromZero(jitter[3], time);
    const double roll = acceleration.dot(RightOf(heading)) / kGravity + SumFromZero(jitter[4], time);
    const Eigen::Vector3d shiver(SumFromZero(jitter[0], time), SumFromZero(jitter[1], time),
                                 SumFromZero(jitter[2], time));
    (*poses)[k].world_from_cam = Rigid3d(Attitude(heading, pitch, roll), m.from + MinimumJerk(tau) * move + shiver);
  }
}

}  // namespace

CarRoute::CarRoute(const CarMotionConfig& config) : c_(config) {
  turn_ = config.turn_deg * kDegToRad;
  arc_end_m_ = c_.straight_m + c_.turn_radius_m * std::abs(turn_);
}

double CarRoute::Speed(double s) const {
  if (turn_ == 0.0) return c_.cruise_speed_mps;
  const double vt2 = c_.turn_speed_mps * c_.turn_speed_mps;
  if (s < c_.straight_m) return std::min(c_.cruise_speed_mps, std::sqrt(vt2 + 2.0 * c_.brake_mps2 * (c_.straight_m - s)));
  if (s <= arc_end_m_) return c_.turn_speed_mps;
  return std::min(c_.cruise_speed_mps, std::sqrt(vt2 + 2.0 * c_.accelerate_mps2 * (s - arc_end_m_)));
}

double CarRoute::Yaw(double s) const {
  if (s <= c_.straight_m || turn_ == 0.0) return 0.0;
  if (s >= arc_end_m_) return turn_;
  return (turn_ > 0.0 ? 1.0 : -1.0) * (s - c_.straight_m) / c_.turn_radius_m;
}

Eigen::Vector3d CarRoute::Position(double s) const {
  if (s <= c_.straight_m || turn_ == 0.0) return {0.0, 0.0, s};
  const double sign = turn_ > 0.0 ? 1.0 : -1.0, radius = c_.turn_radius_m;
  // On the arc the centre of the turn is radius to the side of the turn's start.
  const Eigen::Vector3d start(0.0, 0.0, c_.straight_m);
  const double yaw = Yaw(std::min(s, arc_end_m_));
  const Eigen::Vector3d on_arc = start + sign * radius * (RightOf(0.0) - RightOf(yaw));
  return s <= arc_end_m_ ? on_arc : Eigen::Vector3d(on_arc + (s - arc_end_m_) * Heading(turn_));
}

double CarRoute::LateralAcceleration(double s) const {
  if (turn_ == 0.0 || s <= c_.straight_m || s >= arc_end_m_) return 0.0;
  return (turn_ > 0.0 ? 1.0 : -1.0) * c_.turn_speed_mps * c_.turn_speed_mps / c_.turn_radius_m;
}

double CarRoute::LongitudinalAcceleration(double s) const {
  // v dv/ds by central differences (exact away from the speed's kinks, 1 cm wide).
  const double h = 0.005;
  return Speed(s) * (Speed(s + h) - Speed(s - h)) / (2.0 * h);
}

std::vector<double> CarRoute::Distances(const std::vector<double>& times) const {
  // ds/dt = Speed(s) by the classical Runge-Kutta method, steps of at most 10 ms.
  std::vector<double> distances(times.size(), 0.0);
  double s = 0.0, t = times.empty() ? 0.0 : times.front();
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double span = times[k] - t;
    const int steps = static_cast<int>(std::ceil(span / 0.01));
    const double h = steps > 0 ? span / steps : 0.0;
    for (int i = 0; i < steps; ++i) {
      const double k1 = Speed(s), k2 = Speed(s + 0.5 * h * k1), k3 = Speed(s + 0.5 * h * k2), k4 = Speed(s + h * k3);
      s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    t = times[k];
    distances[k] = s;
  }
  return distances;
}

namespace {

// Profile "car": along CarRoute, with the body's pitch and roll (relative to the first frame's,
// so that frame 0 is level: the world is the left camera at frame 0).
void CarMotion(const CarMotionConfig& c, RandomStream& rng, Trajectory* poses) {
  const CarRoute route(c);
  std::vector<double> times;
  for (const TimedPose& pose : *poses) times.push_back(pose.time);
  const std::vector<double> distances = route.Distances(times);
  std::array<std::vector<Sinusoid>, 3> suspension;  // pitch, roll, height
  for (int i = 0; i < 3; ++i) {
    suspension[i] = DrawSway(rng, 2, 0.5 * (i < 2 ? c.suspension_deg * kDegToRad : c.suspension_m), 0.5, 2.0);
  }
  const auto body_tilt = [&](double s, double* pitch, double* roll) {
    // Braking (negative acceleration) dips the nose; a turn rolls the body outwards.
    *pitch = c.pitch_per_mps2_deg * kDegToRad * route.LongitudinalAcceleration(s);
    *roll = -c.roll_per_mps2_deg * kDegToRad * route.LateralAcceleration(s);
  };
  double pitch0 = 0.0, roll0 = 0.0;
  body_tilt(0.0, &pitch0, &roll0);
  for (std::size_t k = 1; k < poses->size(); ++k) {
    const double t = (*poses)[k].time - times.front(), s = distances[k];
    double pitch = 0.0, roll = 0.0;
    body_tilt(s, &pitch, &roll);
    pitch += SumFromZero(suspension[0], t) - pitch0;
    roll += SumFromZero(suspension[1], t) - roll0;
    const Eigen::Vector3d centre = route.Position(s) - SumFromZero(suspension[2], t) * Eigen::Vector3d::UnitY();
    (*poses)[k].world_from_cam = Rigid3d(Attitude(route.Yaw(s), pitch, roll), centre);
  }
}
}  // namespace

Trajectory MakeTrajectory(const MotionConfig& config, int frames, double frame_rate, std::uint64_t seed) {
  Trajectory poses(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) poses[k].time = k / frame_rate;
  RandomStream rng = MakeStream(seed, "motion");
  switch (config.profile) {
    case MotionProfile::kNone: break;
    case MotionProfile::kHandheld: HandheldMotion(config.handheld, rng, &poses); return poses;
    case MotionProfile::kMav: MavMotion(config.mav, rng, &poses); return poses;
    case MotionProfile::kCar: CarMotion(config.car, rng, &poses); return poses;
  }
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
