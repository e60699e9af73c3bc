// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Haptic devices: an abstract interface, a simulated device (a handle held by a model hand) and a
/// replay device that plays a recorded trajectory.
///
/// Plugging in a vendor device: derive from HapticDevice and forward the calls, all from the servo
/// thread (the vendor's scheduler callback or hdm::run_servo_loop):
/// - OpenHaptics HD: `begin_frame()` calls `hdBeginFrame(hHD)`, then
///   `hdGetDoublev(HD_CURRENT_POSITION, p)` (millimetres: multiply by 1e-3),
///   `hdGetDoublev(HD_CURRENT_VELOCITY, v)` and `hdGetIntegerv(HD_CURRENT_BUTTONS, &b)`;
///   `end_frame(f)` calls `hdSetDoublev(HD_CURRENT_FORCE, f)` (newtons) and `hdEndFrame(hHD)`.
///   `spec()` comes from `HD_NOMINAL_MAX_FORCE`, `HD_NOMINAL_MAX_STIFFNESS` (N/mm: ×1e3) and
///   `HD_USABLE_WORKSPACE_DIMENSIONS`. Run hdm's tick inside an `hdScheduleAsynchronous` callback
///   (HD_MAX_SCHEDULER_PRIORITY) or set the scheduler rate with `hdSetSchedulerRate`.
/// - Force Dimension DHD: `begin_frame()` calls `dhdGetPosition(&x, &y, &z)` (metres),
///   `dhdGetLinearVelocity(&vx, &vy, &vz)` and `dhdGetButtonMask()`; `end_frame(f)` calls
///   `dhdSetForce(fx, fy, fz)` (or `dhdSetForceAndTorqueAndGripperForce`). Enable forces with
///   `dhdEnableForce(DHD_ON)` before the loop; the loop rate is hdm's (run_servo_loop).
///   A 6-DOF model also fills DeviceState::orientation from `dhdGetOrientationFrame(R)` (the
///   rotation matrix as a quaternion) and DeviceState::angular_velocity from
///   `dhdGetAngularVelocityRad`, and overrides `end_frame(f, t)` with
///   `dhdSetForceAndTorque(fx, fy, fz, tx, ty, tz)`; spec().max_torque_nm > 0 then.
/// Device axes: map the vendor's frame to hdm's device frame (right-handed, metres, the workspace
/// centre at the origin) inside the adapter; hdm::Workspace then maps device to model.

#include <hdm/core/types.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hdm {

/// Capabilities of a device, SI.
struct DeviceSpec {
  double workspace_m = 0.16;            ///< usable workspace diagonal [m]
  double max_force_n = 3.3;             ///< continuous force limit [N]
  double max_stiffness_n_per_m = 2000;  ///< stiffness the vendor rates as stable [N/m]
  double nominal_rate_hz = 1000;        ///< servo rate the device is designed for [Hz]
  /// Continuous torque limit [N·m]; 0: the device renders no torque (3-DOF), and
  /// HapticDevice::end_frame(force, torque) drops the torque.
  double max_torque_nm = 0;
};

/// One reading of the device, device frame.
struct DeviceState {
  Vec3 position = Vec3::Zero();  ///< handle position [m], workspace centre at the origin
  Vec3 velocity = Vec3::Zero();  ///< handle velocity [m/s] (backward difference, as encoders give)
  uint32_t buttons = 0;          ///< button bit mask
  double time_s = 0;             ///< device time of the reading [s]
  /// Handle orientation: unit quaternion rotating the tool frame to the device frame; identity for
  /// a device that does not sense orientation (3-DOF).
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Vec3 angular_velocity = Vec3::Zero();  ///< handle angular velocity [rad/s], device frame; zero for 3-DOF
};

/// Abstract haptic device. One servo tick is begin_frame() → compute → end_frame(force), or
/// end_frame(force, torque) for a tool that renders torque as well.
///
/// Threading: used by the servo thread only. Real-time rule: begin_frame and end_frame must not
/// allocate, lock or do I/O in implementations used in the servo loop.
class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  /// @brief Reads the handle state at the start of a tick.
  /// @return false when the device has nothing more to give (end of a replay) or failed.
  /// @note noexcept, real-time safe.
  virtual bool begin_frame(DeviceState& state) noexcept = 0;
  /// @brief Commands @p force_n [N, device frame] until the next tick and ends the tick.
  /// @note noexcept, real-time safe. Implementations clamp to spec().max_force_n.
  virtual void end_frame(const Vec3& force_n) noexcept = 0;
  /// @brief Commands @p force_n [N] and @p torque_nm [N·m, about the handle's tip point], both
  /// device frame, until the next tick, and ends the tick.
  /// @note noexcept, real-time safe. The default drops the torque and calls end_frame(force_n):
  ///       what a 3-DOF device (spec().max_torque_nm == 0) does. A device that renders torque
  ///       overrides it and clamps the torque to spec().max_torque_nm. A derived class that
  ///       overrides only one overload brings the other in with `using HapticDevice::end_frame;`.
  virtual void end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept {
    (void)torque_nm;
    end_frame(force_n);
  }
  /// Capabilities.
  virtual DeviceSpec spec() const noexcept = 0;
};

/// Settings of SimulatedDevice. Defaults: a light pen-type handle in a compliant grip, turned
/// about its tip by a wrist of the order of a relaxed human wrist's stiffness.
struct SimulatedDeviceOptions {
  double mass_kg = 0.05;          ///< handle plus linkage mass [kg]
  double hand_stiffness = 200.0;  ///< hand spring pulling the handle to the target [N/m]
  double hand_damping = 2.0;      ///< hand damper on the handle's velocity relative to the target [N·s/m]
  double rate_hz = 1000.0;        ///< servo rate: the rendered force is held for 1/rate_hz [Hz]
  int substeps = 10;              ///< semi-implicit Euler steps per servo period (force held: zero-order hold)
  DeviceSpec spec;                ///< reported capabilities (max force and max torque clamps)
  /// Handle orientation at the start (tool → device frame, at rest), and the wrist's target when
  /// no per-tick orientation targets are given. Normalised at construction.
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  /// Rotational inertia of the handle about its tip point [kg·m²], isotropic. 1e-4: a pen of about
  /// 20 g and 12 cm turned about its nib (m·L²/3), the gimbal's own inertia being smaller.
  double inertia_kgm2 = 1e-4;
  /// Wrist spring turning the handle toward the target orientation [N·m/rad], >= 0; +infinity: the
  /// hand holds the orientation rigidly at the target (a commanded torque turns nothing). 1: the
  /// order of the relaxed wrist's passive stiffness (Formica et al. 2012, J Neurophysiol 108); a
  /// braced grip is stiffer. With the inertia, the handle rings at sqrt(k/I) = 100 rad/s (16 Hz).
  double wrist_stiffness = 1.0;
  /// Wrist damper on the handle's angular velocity relative to the target's [N·m·s/rad], >= 0.
  /// 0.006: damping ratio b / (2·sqrt(k·I)) = 0.3, as the translational grip's defaults give
  /// (2 / (2·sqrt(200 · 0.05)) = 0.32); also far above the k_r·T/2 that passivity against a
  /// rotational coupling k_r needs (Colgate & Schenkel 1997; 1e-4 for k_r = 0.2 N·m/rad at 1 kHz).
  double wrist_damping = 0.006;
};

/// A simulated device: a handle of mass m pulled by a hand spring-damper toward a scripted target
/// path, and pushed by the rendered force, which is held constant over each servo period (zero-order
/// hold, as a real amplifier does). Integrated by semi-implicit Euler with `substeps` steps per period.
///
/// The closed loop (render → hold → handle motion → next reading) is what limits stable stiffness
/// (Colgate & Schenkel 1997: passivity needs b > K·T/2); the substeps keep the integrator itself
/// out of that limit.
///
/// Rotation: the handle turns about its tip point (the point whose position it reports, as a
/// gimbal whose axes meet there) with inertia I, pulled toward the target orientation by the wrist's
/// spring k·θ (θ the rotation vector from the handle to the target) and damper −b·(ω − ω_target),
/// and turned by the commanded torque (clamped to spec().max_torque_nm, NaN → 0), held over the
/// period like the force. Per substep h: ω += h·(τ_wrist + τ)/I, then q ← exp(ω·h)·q, renormalised
/// (semi-implicit Euler on the unit quaternion; no gyroscopic term, the inertia being isotropic).
/// The target moves between ticks at the constant angular velocity that takes one tick's target
/// to the next. A constant torque τ from rest turns a free handle (k = 0, b = 0) by τ·t²/(2I); with
/// the wrist the handle settles τ/k from the target. With wrist_stiffness = +infinity the
/// orientation is the target's, whatever the torque.
class SimulatedDevice final : public HapticDevice {
 public:
  /// @brief Creates the device; @p targets holds one hand target [m] per tick (the last one is held
  /// after the end). The spans must outlive the device.
  /// @param options  handle mass and inertia, hand and wrist springs and dampers, rate, substeps and
  ///                 the device spec.
  /// @param targets  hand target per tick [m, device frame].
  /// @param start    initial handle position [m] (at rest).
  /// @param buttons  optional button mask per tick (the hand pressing the tool button; the last
  ///                 one is held after the end); empty: no button pressed.
  /// @param orientation_targets  optional target orientation per tick (tool → device frame; need
  ///                 not be unit, normalised on use; the last one is held after the end); empty:
  ///                 options.orientation throughout. The handle starts at options.orientation.
  /// @throws InvalidInput when mass_kg, inertia_kgm2 or rate_hz is not positive, substeps < 1,
  ///         wrist_stiffness or wrist_damping is negative or NaN (or the damping infinite), or the
  ///         orientation or an orientation target is not a finite non-zero quaternion (naming its tick).
  SimulatedDevice(const SimulatedDeviceOptions& options, std::span<const Vec3> targets, const Vec3& start,
                  std::span<const uint32_t> buttons = {}, std::span<const Eigen::Quaterniond> orientation_targets = {});
  /// Handle position [m] and backward-difference velocity [m/s], the tick's buttons, orientation
  /// (unit) and backward-difference angular velocity [rad/s, device frame]; always true.
  /// noexcept, O(1).
  bool begin_frame(DeviceState& state) noexcept override;
  /// Holds @p force_n [N] (clamped to spec().max_force_n, NaN → 0) and no torque over one period
  /// and integrates the handle; the recorded torque becomes zero. noexcept, O(substeps), no allocation.
  void end_frame(const Vec3& force_n) noexcept override;
  /// As end_frame(force_n), with @p torque_nm [N·m, device frame, about the tip] clamped to
  /// spec().max_torque_nm (NaN → 0; 0 when the spec renders no torque) held over the period as
  /// well; it is recorded (last_torque()). noexcept, O(substeps), no allocation.
  void end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept override;
  /// Torque commanded in the last period after the clamp [N·m, device frame].
  const Vec3& last_torque() const noexcept { return torque_; }
  /// The options' spec.
  DeviceSpec spec() const noexcept override { return options_.spec; }
  /// Hand force on the handle during the last period [N] (what the user pushes with).
  const Vec3& hand_force() const noexcept { return hand_force_; }
  /// Wrist torque on the handle during the last period [N·m, device frame] (what the user twists
  /// with); zero when the orientation is held rigidly.
  const Vec3& wrist_torque() const noexcept { return wrist_torque_; }
  /// Tick counter.
  int64_t tick() const noexcept { return tick_; }

 private:
  void integrate_rotation(double period) noexcept;

  SimulatedDeviceOptions options_;
  std::span<const Vec3> targets_;
  std::span<const uint32_t> buttons_;
  std::span<const Eigen::Quaterniond> orientation_targets_;
  Vec3 x_, v_, x_prev_, hand_force_ = Vec3::Zero(), torque_ = Vec3::Zero();
  Eigen::Quaterniond q_, q_prev_;
  Vec3 w_ = Vec3::Zero(), wrist_torque_ = Vec3::Zero();
  int64_t tick_ = 0;
};

/// Plays back a CSV trajectory written by `hdm sculpt --forces` (header
/// `time_s,device_x_m,device_y_m,device_z_m,...`): one row per tick; forces are ignored. An
/// optional `tool_on` column (0 or 1) is the tool button (bit 0 of DeviceState::buttons), so a
/// replayed sculpting session strokes where the recorded one did. Optional columns
/// `device_qw,device_qx,device_qy,device_qz` (all four or none; `hdm sculpt --forces` writes them)
/// are the handle's orientation, a quaternion (tool → device frame) normalised on read; the angular
/// velocity is their backward difference (the rotation vector from one row's orientation to the
/// next over the time between them [rad/s, device frame]). Without them the orientation reads
/// identity and the angular velocity zero. A commanded torque is kept (last_torque()) and not
/// played anywhere.
class ReplayDevice final : public HapticDevice {
 public:
  /// @brief Loads @p csv_path (all rows read here, so frames never do I/O).
  /// @param csv_path  the recording (CSV, see the class).
  /// @param spec      the device's workspace, rate and force limit reported by spec().
  /// @param max_file_bytes  a larger file is refused before it is read (default 1 GiB, about
  ///                        ten million rows as `hdm sculpt --forces` writes them).
  /// @throws IoError when the file cannot be read or is larger than @p max_file_bytes;
  /// InvalidInput when the header lacks the position columns or has some of the orientation
  /// columns but not all four, a row is malformed, a time or position is not finite (NaN, inf),
  /// the time goes backwards, tool_on is not 0 or 1, or a row's orientation quaternion is not
  /// finite or zero (norm below 1e-6) (each naming the file and line).
  /// @note Accepts "\n" and "\r\n" line ends and blanks around cells; O(file size).
  explicit ReplayDevice(const std::string& csv_path, DeviceSpec spec = {}, uint64_t max_file_bytes = uint64_t(1) << 30);
  /// @brief Loads a recording from CSV text held in memory, as the constructor loads a file;
  /// @p name starts every error message.
  /// @throws InvalidInput as the constructor.
  static ReplayDevice from_csv(std::string_view csv, const std::string& name, DeviceSpec spec = {});
  /// Next recorded row (velocity and angular velocity by backward difference); false after the
  /// last one. noexcept, O(1).
  bool begin_frame(DeviceState& state) noexcept override;
  /// Records @p force_n [N] (see last_force()) and advances to the next row. noexcept, O(1).
  void end_frame(const Vec3& force_n) noexcept override;
  /// Records @p force_n [N] and @p torque_nm [N·m] (see last_torque()) and advances. noexcept, O(1).
  void end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept override;
  /// The spec given at construction.
  DeviceSpec spec() const noexcept override { return spec_; }
  /// Number of recorded ticks.
  size_t size() const noexcept { return position_.size(); }
  /// Mean tick rate of the recording [Hz]: (rows - 1) / recorded duration; 0 for one row or no duration.
  double rate_hz() const noexcept;
  /// Last commanded force [N].
  const Vec3& last_force() const noexcept { return last_force_; }
  /// Last commanded torque [N·m] (zero after a force-only end_frame).
  const Vec3& last_torque() const noexcept { return last_torque_; }

 private:
  ReplayDevice() = default;
  void parse(std::string_view csv, const std::string& name);

  DeviceSpec spec_;
  std::vector<double> time_;
  std::vector<Vec3> position_;
  std::vector<uint32_t> buttons_;                // empty without a tool_on column
  std::vector<Eigen::Quaterniond> orientation_;  // unit; empty without the orientation columns
  size_t next_ = 0;
  Vec3 last_force_ = Vec3::Zero();
  Vec3 last_torque_ = Vec3::Zero();
};

}  // namespace hdm
