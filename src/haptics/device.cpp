// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/haptics/device.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace hdm {

SimulatedDevice::SimulatedDevice(const SimulatedDeviceOptions& o, std::span<const Vec3> targets, const Vec3& start,
                                 std::span<const uint32_t> buttons)
    : options_(o), targets_(targets), buttons_(buttons), x_(start), v_(Vec3::Zero()), x_prev_(start) {
  if (!(o.mass_kg > 0) || !(o.rate_hz > 0) || o.substeps < 1)
    throw InvalidInput("SimulatedDevice: mass_kg and rate_hz must be > 0 and substeps >= 1");
}

bool SimulatedDevice::begin_frame(DeviceState& s) noexcept {
  const double dt = 1.0 / options_.rate_hz;
  s.position = x_;
  s.velocity = tick_ > 0 ? Vec3((x_ - x_prev_) / dt) : Vec3::Zero();
  s.buttons = buttons_.empty() ? 0u : buttons_[std::min<size_t>(static_cast<size_t>(tick_), buttons_.size() - 1)];
  s.time_s = tick_ * dt;
  return true;
}

void SimulatedDevice::end_frame(const Vec3& force_n) noexcept {
  Vec3 f = force_n.allFinite() ? force_n : Vec3::Zero();
  const double mag = f.norm();
  if (mag > options_.spec.max_force_n) f *= options_.spec.max_force_n / mag;  // amplifier saturation
  const Vec3 target = targets_.empty() ? x_ : targets_[std::min<size_t>(tick_, targets_.size() - 1)];
  const Vec3 target_next =
      targets_.empty() ? x_ : targets_[std::min<size_t>(tick_ + 1, targets_.size() - 1)];
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
  ++tick_;
}

ReplayDevice::ReplayDevice(const std::string& path, DeviceSpec spec) : spec_(spec) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot read");
  std::string line;
  if (!std::getline(in, line)) throw InvalidInput(path + ": empty file");
  // Locate the columns by name so that extra columns may follow.
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
  }
  auto col = [&](const char* name) {
    const auto it = std::find(cols.begin(), cols.end(), name);
    if (it == cols.end()) throw InvalidInput(path + ": header lacks column " + name);
    return static_cast<size_t>(it - cols.begin());
  };
  const size_t ct = col("time_s"), cx = col("device_x_m"), cy = col("device_y_m"), cz = col("device_z_m");
  std::vector<double> v;
  for (int64_t no = 2; std::getline(in, line); ++no) {
    if (line.empty()) continue;
    v.clear();
    const char* p = line.c_str();
    while (*p) {
      char* end;
      v.push_back(std::strtod(p, &end));
      if (end == p) throw InvalidInput(path + ":" + std::to_string(no) + ": malformed number");
      p = end;
      if (*p == ',') ++p;
    }
    if (v.size() < cols.size()) throw InvalidInput(path + ":" + std::to_string(no) + ": too few columns");
    const std::string where = path + ":" + std::to_string(no) + ": ";
    if (!std::isfinite(v[ct]) || !std::isfinite(v[cx]) || !std::isfinite(v[cy]) || !std::isfinite(v[cz]))
      throw InvalidInput(where + "time or position is not a finite number");
    if (!time_.empty() && v[ct] < time_.back()) throw InvalidInput(where + "time goes backwards");
    time_.push_back(v[ct]);
    position_.emplace_back(v[cx], v[cy], v[cz]);
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
  s.buttons = 0;
  return true;
}

void ReplayDevice::end_frame(const Vec3& force_n) noexcept {
  last_force_ = force_n;
  ++next_;
}

}  // namespace hdm
