#include "tools/soak/malformed.hpp"

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>

namespace dammloam::soak {
namespace {

struct Breaker {
  MalformedKind kind;
  std::function<void(dds::CloudMessage&)> corrupt;
};

void SetCoordinate(dds::CloudMessage& m, std::size_t point, std::size_t axis, float value) {
  std::memcpy(m.data.data() + point * m.point_step + 4 * axis, &value, sizeof(value));
}

dds::CloudField* Field(dds::CloudMessage& m, const std::string& name) {
  for (auto& f : m.fields) {
    if (f.name == name) return &f;
  }
  throw std::logic_error("soak: the valid cloud has no field '" + name + "'");
}

void MakeOversized(dds::CloudMessage& m) {
  const std::vector<std::uint8_t> scan = m.data;
  m.width = static_cast<std::uint32_t>(3 * kMaxCloudBytes / 2 / m.point_step);
  m.row_step = m.width * m.point_step;
  m.data.clear();
  while (m.data.size() < m.row_step) m.data.insert(m.data.end(), scan.begin(), scan.end());
  m.data.resize(m.row_step);  // well formed: only its size is wrong
}

dammloam_msg_Time SecondsEarlier(dammloam_msg_Time t, double seconds) {
  return dds::ToMsgTime(dds::ToSeconds(t) - seconds);
}

const std::vector<Breaker>& Breakers() {
  static const std::vector<Breaker> breakers = {
      {{"nan_point", "non_finite"},
       [](auto& m) { SetCoordinate(m, m.width / 2, 0, std::numeric_limits<float>::quiet_NaN()); }},
      {{"empty_cloud", "zero_points"},
       [](auto& m) {
         m.width = 0;
         m.row_step = 0;
         m.data.clear();
       }},
      {{"truncated_data", "payload_size"}, [](auto& m) { m.data.resize(m.data.size() / 2); }},
      {{"missing_x", "missing_field"},
       [](auto& m) { m.fields.erase(m.fields.begin() + (Field(m, "x") - m.fields.data())); }},
      {{"duplicate_stamp", "duplicate_stamp"}, [](auto&) {}},  // the stamp of the scan just sent
      {{"x_wrong_datatype", "field_type"},
       [](auto& m) { Field(m, "x")->datatype = dammloam_msg_DATATYPE_UINT32; }},
      {{"older_stamp", "out_of_order_stamp"},
       [](auto& m) { m.stamp = SecondsEarlier(m.stamp, 0.5); }},
      {{"inf_point", "non_finite"},
       [](auto& m) { SetCoordinate(m, m.width / 3, 2, std::numeric_limits<float>::infinity()); }},
      {{"oversized", "too_large"}, MakeOversized},
  };
  return breakers;
}

bool BreaksTheStamp(const MalformedKind& kind) {
  return kind.code == "duplicate_stamp" || kind.code == "out_of_order_stamp";
}

}  // namespace

const std::vector<MalformedKind>& MalformedKinds() {
  static const std::vector<MalformedKind> kinds = [] {
    std::vector<MalformedKind> k;
    for (const Breaker& b : Breakers()) k.push_back(b.kind);
    return k;
  }();
  return kinds;
}

std::optional<std::size_t> MalformedAfter(std::size_t scan, double rate) {
  if (!(rate > 0.0)) return std::nullopt;
  // Malformed samples due up to and including scan k: floor((k + 1) * rate). The epsilon keeps
  // 100 * 0.01 from rounding below 1.
  const auto due_through = [rate](std::size_t k) {
    return static_cast<std::size_t>(std::floor(static_cast<double>(k) * rate + 1e-9));
  };
  const std::size_t before = due_through(scan), after = due_through(scan + 1);
  if (after == before) return std::nullopt;
  return (after - 1) % Breakers().size();
}

dds::CloudMessage MakeMalformed(std::size_t kind, const dds::CloudMessage& valid) {
  const Breaker& breaker = Breakers().at(kind);
  dds::CloudMessage bad = valid;
  // A content problem gets a stamp of its own (1 ms after the scan): should the daemon miss the
  // problem, it would accept the sample instead of hiding it behind a duplicate-stamp rejection.
  if (!BreaksTheStamp(breaker.kind)) bad.stamp = dds::ToMsgTime(dds::ToSeconds(valid.stamp) + 1e-3);
  breaker.corrupt(bad);
  return bad;
}

}  // namespace dammloam::soak
