// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/haptics/device.h>

#include "rotation.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>

namespace hdm {

namespace {

using haptics_detail::from_rotation_vector;
using haptics_detail::rotation_vector;
using Quat = Eigen::Quaterniond;

bool usable_quaternion(const Quat& q) noexcept { return q.coeffs().allFinite() && q.norm() > 0; }

// @p v shortened to length @p cap if longer; NaN or infinite → zero (an amplifier's saturation).
Vec3 clamp_length(const Vec3& v, double cap) noexcept {
  if (!v.allFinite()) return Vec3::Zero();
  const double mag = v.norm();
  cap = std::max(0.0, cap);
  return mag > cap ? Vec3(v * (cap / mag)) : v;
}

// A recording's optional orientation columns, all four or none.
constexpr const char* kOrientationColumns[4] = {"device_qw", "device_qx", "device_qy", "device_qz"};

// Where the orientation columns are in the header @p cols; none when it has none of them.
// @throws InvalidInput naming @p path when it has some but not all four.
std::optional<std::array<size_t, 4>> orientation_columns(const std::vector<std::string_view>& cols,
                                                         const std::string& path) {
  std::array<size_t, 4> at{};
  int found = 0;
  for (int i = 0; i < 4; ++i) {
    at[i] = static_cast<size_t>(std::find(cols.begin(), cols.end(), kOrientationColumns[i]) - cols.begin());
    found += at[i] < cols.size();
  }
  if (found == 0) return std::nullopt;
  for (int i = 0; i < 4; ++i)
    if (at[i] == cols.size())
      throw InvalidInput(path + ": header lacks column " + kOrientationColumns[i] +
                         " (the orientation columns device_qw,device_qx,device_qy,device_qz come all four or none)");
  return at;
}

// A row's orientation, normalised. @throws InvalidInput after @p where when it is not finite or zero.
Quat read_orientation(const std::vector<double>& v, const std::array<size_t, 4>& c, const std::string& where) {
  const Quat q(v[c[0]], v[c[1]], v[c[2]], v[c[3]]);
  if (!q.coeffs().allFinite())
    throw InvalidInput(where + "orientation (device_qw,device_qx,device_qy,device_qz) is not a finite quaternion");
  if (!(q.norm() >= 1e-6))
    throw InvalidInput(where + "orientation (device_qw,device_qx,device_qy,device_qz) is a zero quaternion (norm " +
                       "below 1e-6)");
  return q.normalized();
}

}  // namespace

SimulatedDevice::SimulatedDevice(const SimulatedDeviceOptions& o, std::span<const Vec3> targets, const Vec3& start,
                                 std::span<const uint32_t> buttons, std::span<const Quat> orientation_targets)
    : options_(o),
      targets_(targets),
      buttons_(buttons),
      orientation_targets_(orientation_targets),
      x_(start),
      v_(Vec3::Zero()),
      x_prev_(start) {
  if (!(o.mass_kg > 0) || !(o.rate_hz > 0) || o.substeps < 1)
    throw InvalidInput("SimulatedDevice: mass_kg and rate_hz must be > 0 and substeps >= 1");
  if (!(o.inertia_kgm2 > 0) || !std::isfinite(o.inertia_kgm2))
    throw InvalidInput("SimulatedDevice: inertia_kgm2 must be finite and > 0");
  if (!(o.wrist_stiffness >= 0) || !(o.wrist_damping >= 0) || !std::isfinite(o.wrist_damping))
    throw InvalidInput(
        "SimulatedDevice: wrist_stiffness must be >= 0 (+infinity: held rigidly) and wrist_damping finite and >= 0");
  if (!usable_quaternion(o.orientation))
    throw InvalidInput("SimulatedDevice: the orientation must be a finite, non-zero quaternion");
  for (size_t k = 0; k < orientation_targets.size(); ++k)
    if (!usable_quaternion(orientation_targets[k]))
      throw InvalidInput("SimulatedDevice: the orientation target of tick " + std::to_string(k) +
                         " is not a finite, non-zero quaternion");
  options_.orientation.normalize();
  q_ = q_prev_ = options_.orientation;
}

bool SimulatedDevice::begin_frame(DeviceState& s) noexcept {
  const double dt = 1.0 / options_.rate_hz;
  s.position = x_;
  s.velocity = tick_ > 0 ? Vec3((x_ - x_prev_) / dt) : Vec3::Zero();
  s.buttons = buttons_.empty() ? 0u : buttons_[std::min<size_t>(static_cast<size_t>(tick_), buttons_.size() - 1)];
  s.time_s = tick_ * dt;
  s.orientation = q_;
  s.angular_velocity = tick_ > 0 ? Vec3(rotation_vector(q_ * q_prev_.conjugate()) / dt) : Vec3::Zero();
  return true;
}

void SimulatedDevice::end_frame(const Vec3& force_n) noexcept { end_frame(force_n, Vec3::Zero()); }

void SimulatedDevice::end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept {
  const Vec3 f = clamp_length(force_n, options_.spec.max_force_n);
  torque_ = clamp_length(torque_nm, options_.spec.max_torque_nm);
  const Vec3 target = targets_.empty() ? x_ : targets_[std::min<size_t>(tick_, targets_.size() - 1)];
  const Vec3 target_next = targets_.empty() ? x_ : targets_[std::min<size_t>(tick_ + 1, targets_.size() - 1)];
  const double T = 1.0 / options_.rate_hz, h = T / options_.substeps;
  const Vec3 target_v = (target_next - target) / T;
  x_prev_ = x_;
  hand_force_.setZero();
  for (int k = 0; k < options_.substeps; ++k) {
    const Vec3 tk = target + target_v * (k * h);  // the hand moves smoothly between ticks
    const Vec3 hand = options_.hand_stiffness * (tk - x_) - options_.hand_damping * (v_ - target_v);
    v_ += h * (hand + f) / options_.mass_kg;  // semi-implicit Euler: velocity first,
    x_ += h * v_;                             // then position with the new velocity
    hand_force_ += hand / options_.substeps;
  }
  integrate_rotation(T);
  ++tick_;
}

void SimulatedDevice::integrate_rotation(double T) noexcept {
  auto target_at = [&](int64_t tick) {
    if (orientation_targets_.empty()) return options_.orientation;
    return orientation_targets_[std::min<size_t>(static_cast<size_t>(tick), orientation_targets_.size() - 1)]
        .normalized();
  };
  const Quat target = target_at(tick_), target_next = target_at(tick_ + 1);
  const Vec3 target_w = rotation_vector(target_next * target.conjugate()) / T;  // device frame
  q_prev_ = q_;
  wrist_torque_.setZero();
  if (std::isinf(options_.wrist_stiffness)) {  // held rigidly: the handle is where the hand puts it
    q_ = target_next;
    w_ = target_w;
    return;
  }
  const double h = T / options_.substeps, k = options_.wrist_stiffness, b = options_.wrist_damping;
  for (int i = 0; i < options_.substeps; ++i) {
    const Quat ti = from_rotation_vector(target_w * (i * h)) * target;  // the hand turns smoothly between ticks
    const Vec3 wrist = k * rotation_vector(ti * q_.conjugate()) - b * (w_ - target_w);
    w_ += h * (wrist + torque_) / options_.inertia_kgm2;    // semi-implicit: angular velocity first,
    q_ = (from_rotation_vector(w_ * h) * q_).normalized();  // then the orientation with the new one
    wrist_torque_ += wrist / options_.substeps;
  }
}

ReplayDevice::ReplayDevice(const std::string& path, DeviceSpec spec, uint64_t max_file_bytes) : spec_(spec) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path + ": cannot read (" + ec.message() + ")");
  if (size > max_file_bytes)
    throw IoError(path + ": " + std::to_string(size) + " bytes, more than the input limit of " +
                  std::to_string(max_file_bytes) + " bytes; raise the limit to read it (hdm: --max-input-mb)");
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<size_t>(size), '\0');
  if (!in || (size > 0 && !in.read(text.data(), static_cast<std::streamsize>(size))))
    throw IoError(path + ": cannot read");
  parse(text, path);
}

ReplayDevice ReplayDevice::from_csv(std::string_view csv, const std::string& name, DeviceSpec spec) {
  ReplayDevice d;
  d.spec_ = spec;
  d.parse(csv, name);
  return d;
}

void ReplayDevice::parse(std::string_view text, const std::string& path) {
  // One line at a time, without its line end ("\n" or "\r\n").
  size_t pos = 0;
  auto next_line = [&](std::string_view& line) {
    if (pos >= text.size()) return false;
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    line = text.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = end + 1;
    return true;
  };
  auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
  };
  std::string_view line;
  if (!next_line(line)) throw InvalidInput(path + ": empty file");
  // Locate the columns by name so that extra columns may follow.
  std::vector<std::string_view> cols;
  for (size_t start = 0;;) {
    const size_t comma = line.find(',', start);
    cols.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  auto col = [&](const char* name) {
    const auto it = std::find(cols.begin(), cols.end(), name);
    if (it == cols.end()) throw InvalidInput(path + ": header lacks column " + name);
    return static_cast<size_t>(it - cols.begin());
  };
  const size_t ct = col("time_s"), cx = col("device_x_m"), cy = col("device_y_m"), cz = col("device_z_m");
  // Optional: the tool button as `hdm sculpt --forces` records it (0 or 1).
  const auto tool_it = std::find(cols.begin(), cols.end(), "tool_on");
  const bool has_tool = tool_it != cols.end();
  const size_t ctool = static_cast<size_t>(tool_it - cols.begin());
  const std::optional<std::array<size_t, 4>> cq = orientation_columns(cols, path);
  std::vector<double> v;
  for (int64_t no = 2; next_line(line); ++no) {
    if (trim(line).empty()) continue;
    v.clear();
    const std::string where = path + ":" + std::to_string(no) + ": ";
    for (size_t start = 0; start == 0 || start < line.size();) {  // one number per cell; a trailing comma ends the row
      size_t comma = line.find(',', start);
      if (comma == std::string_view::npos) comma = line.size();
      std::string_view cell = trim(line.substr(start, comma - start));
      if (cell.size() > 1 && cell[0] == '+') cell.remove_prefix(1);
      double x = 0;
      const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), x);
      if (cell.empty() || end != cell.data() + cell.size() ||
          (ec != std::errc() && ec != std::errc::result_out_of_range))
        throw InvalidInput(where + "malformed number in column " + std::to_string(v.size() + 1));
      v.push_back(ec == std::errc() ? x : INFINITY);  // out of range: refused below if it is used
      start = comma + 1;
    }
    if (v.size() < cols.size()) throw InvalidInput(where + "too few columns");
    if (!std::isfinite(v[ct]) || !std::isfinite(v[cx]) || !std::isfinite(v[cy]) || !std::isfinite(v[cz]))
      throw InvalidInput(where + "time or position is not a finite number");
    if (!time_.empty() && v[ct] < time_.back()) throw InvalidInput(where + "time goes backwards");
    if (has_tool && v[ctool] != 0 && v[ctool] != 1) throw InvalidInput(where + "tool_on is neither 0 nor 1");
    time_.push_back(v[ct]);
    position_.emplace_back(v[cx], v[cy], v[cz]);
    if (has_tool) buttons_.push_back(static_cast<uint32_t>(v[ctool]));
    if (cq) orientation_.push_back(read_orientation(v, *cq, where));
  }
  if (position_.empty()) throw InvalidInput(path + ": no rows");
}

double ReplayDevice::rate_hz() const noexcept {
  const double span = time_.back() - time_.front();
  return position_.size() > 1 && span > 0 ? double(position_.size() - 1) / span : 0.0;
}

bool ReplayDevice::begin_frame(DeviceState& s) noexcept {
  if (next_ >= position_.size()) return false;
  s.position = position_[next_];
  s.time_s = time_[next_];
  const double dt = next_ > 0 ? time_[next_] - time_[next_ - 1] : 0;
  s.velocity = dt > 0 ? Vec3((position_[next_] - position_[next_ - 1]) / dt) : Vec3::Zero();
  s.buttons = buttons_.empty() ? 0u : buttons_[next_];
  s.orientation = orientation_.empty() ? Quat::Identity() : orientation_[next_];
  s.angular_velocity = orientation_.empty() || !(dt > 0)
                           ? Vec3::Zero()
                           : Vec3(rotation_vector(orientation_[next_] * orientation_[next_ - 1].conjugate()) / dt);
  return true;
}

void ReplayDevice::end_frame(const Vec3& force_n) noexcept { end_frame(force_n, Vec3::Zero()); }

void ReplayDevice::end_frame(const Vec3& force_n, const Vec3& torque_nm) noexcept {
  last_force_ = force_n;
  last_torque_ = torque_nm;
  ++next_;
}

}  // namespace hdm
