#include "io/motion_csv.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <string_view>

#include "io/io_error.hpp"
#include "io/number_text.hpp"

namespace dammloam::io {
namespace {

namespace fs = std::filesystem;
using Row = std::array<double, 7>;

std::string_view Trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

// Splits one data line into seven numbers; nan and inf parse (they are faults, not syntax).
Row ParseRow(const std::string& text, const std::string& where) {
  Row row{};
  std::size_t begin = 0;
  for (std::size_t i = 0; i < row.size(); ++i) {
    const std::size_t comma = text.find(',', begin);
    const bool last = i + 1 == row.size();
    if (last != (comma == std::string::npos)) {
      std::size_t fields = 1;
      for (const char c : text) fields += c == ',' ? 1 : 0;
      throw IoError(where + "has " + std::to_string(fields) + " fields, expected 7");
    }
    const std::string_view token =
        std::string_view(text).substr(begin, last ? std::string::npos : comma - begin);
    const auto value = ParseDouble(token);
    if (!value) {
      throw IoError(where + "field " + std::to_string(i + 1) + " '" + std::string(Trim(token)) +
                    "' is not a number");
    }
    row[i] = *value;
    begin = comma + 1;
  }
  return row;
}

// Reads every well-formed row of `file`, handing each kept one to `keep`.
void ReadRows(const fs::path& file, const char* header, const char* what, StreamReadReport* report,
              const StreamReadOptions& options, const std::function<void(const Row&)>& keep) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot open " + what);
  StreamReadReport local;
  StreamReadReport& r = report ? *report : local;
  r = StreamReadReport{};
  std::string text;
  int line = 0;
  bool header_seen = false;
  double last_t = -INFINITY;
  while (std::getline(in, text)) {
    ++line;
    const std::string where = file.string() + ":" + std::to_string(line) + ": ";
    if (Trim(text).empty()) continue;
    if (!header_seen) {
      if (Trim(text) != header) {
        throw IoError(where + "header must be '" + std::string(header) + "', got '" +
                      std::string(Trim(text)) + "'");
      }
      header_seen = true;
      continue;
    }
    const Row row = ParseRow(text, where);
    std::optional<SampleFault> fault;
    bool finite = true;
    for (const double v : row) finite = finite && std::isfinite(v);
    if (!finite) {
      fault = SampleFault::kNonFinite;
    } else if (row[0] == last_t) {
      fault = SampleFault::kDuplicateStamp;
    } else if (row[0] < last_t) {
      fault = SampleFault::kOutOfOrderStamp;
    }
    if (!fault) {
      last_t = row[0];
      ++r.kept;
      keep(row);
      continue;
    }
    if (options.strict) {
      throw IoError(where + FaultName(*fault) +
                    (*fault == SampleFault::kNonFinite
                         ? std::string(" in '") + std::string(Trim(text)) + "'"
                         : " " + FormatExact(row[0]) + " after " + FormatExact(last_t)) +
                    " (stamps must be strictly increasing and values finite)");
    }
    switch (*fault) {
      case SampleFault::kNonFinite: ++r.non_finite; break;
      case SampleFault::kDuplicateStamp: ++r.duplicate_stamp; break;
      case SampleFault::kOutOfOrderStamp: ++r.out_of_order; break;
    }
    if (r.first_dropped.size() < StreamReadReport::kMaxListed) r.first_dropped.push_back({line, *fault});
  }
  if (!header_seen) throw IoError(file.string() + ": empty, expected the header '" + header + "'");
}

template <class Sample>
void WriteRows(const fs::path& file, const char* header, const std::vector<Sample>& samples,
               const std::function<Row(const Sample&)>& row_of) {
  std::ofstream out(file, std::ios::trunc);
  if (!out) throw IoError(file.string() + ": cannot create");
  out << header << '\n';
  double last_t = -INFINITY;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Row row = row_of(samples[i]);
    for (const double v : row) {
      if (!std::isfinite(v)) throw IoError(file.string() + ": sample " + std::to_string(i) + " is not finite");
    }
    if (!(row[0] > last_t)) {
      throw IoError(file.string() + ": sample " + std::to_string(i) + " at " + FormatExact(row[0]) +
                    " is not after the previous one at " + FormatExact(last_t));
    }
    last_t = row[0];
    for (std::size_t k = 0; k < row.size(); ++k) out << (k ? "," : "") << FormatExact(row[k]);
    out << '\n';
  }
  if (!out) throw IoError(file.string() + ": cannot write");
}

}  // namespace

const char* FaultName(SampleFault fault) {
  switch (fault) {
    case SampleFault::kNonFinite: return "NaN/inf value";
    case SampleFault::kDuplicateStamp: return "duplicate stamp";
    case SampleFault::kOutOfOrderStamp: return "stamp before the previous one";
  }
  return "unknown fault";
}

std::string StreamReadReport::Summary() const {
  if (dropped() == 0) return "";
  std::string text = "dropped " + std::to_string(dropped()) + ":";
  const char* sep = " ";
  for (const auto& [count, fault] : {std::pair{non_finite, SampleFault::kNonFinite},
                                     std::pair{duplicate_stamp, SampleFault::kDuplicateStamp},
                                     std::pair{out_of_order, SampleFault::kOutOfOrderStamp}}) {
    if (count == 0) continue;
    text += sep + std::to_string(count) + " " + FaultName(fault);
    sep = ", ";
  }
  if (!first_dropped.empty()) {
    text += " (first at line " + std::to_string(first_dropped.front().line) + ": " +
            FaultName(first_dropped.front().fault) + ")";
  }
  return text;
}

std::vector<ImuSample> ReadImuCsv(const fs::path& file, StreamReadReport* report,
                                  const StreamReadOptions& options) {
  std::vector<ImuSample> samples;
  ReadRows(file, kImuCsvHeader, "IMU samples (imu.csv)", report, options, [&](const Row& r) {
    samples.push_back({r[0], {r[1], r[2], r[3]}, {r[4], r[5], r[6]}});
  });
  return samples;
}

std::vector<WheelSample> ReadWheelCsv(const fs::path& file, StreamReadReport* report,
                                      const StreamReadOptions& options) {
  std::vector<WheelSample> samples;
  ReadRows(file, kWheelCsvHeader, "wheel odometry (wheel.csv)", report, options, [&](const Row& r) {
    samples.push_back({r[0], {r[1], r[2], r[3]}, {r[4], r[5], r[6]}});
  });
  return samples;
}

void WriteImuCsv(const fs::path& file, const std::vector<ImuSample>& samples) {
  WriteRows<ImuSample>(file, kImuCsvHeader, samples, [](const ImuSample& s) {
    const Eigen::Vector3d& w = s.angular_velocity;
    const Eigen::Vector3d& a = s.linear_acceleration;
    return Row{s.t, w.x(), w.y(), w.z(), a.x(), a.y(), a.z()};
  });
}

void WriteWheelCsv(const fs::path& file, const std::vector<WheelSample>& samples) {
  WriteRows<WheelSample>(file, kWheelCsvHeader, samples, [](const WheelSample& s) {
    const Eigen::Vector3d& v = s.linear_velocity;
    const Eigen::Vector3d& w = s.angular_velocity;
    return Row{s.t, v.x(), v.y(), v.z(), w.x(), w.y(), w.z()};
  });
}

}  // namespace dammloam::io
