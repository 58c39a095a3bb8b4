#pragma once
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dammloam::drivers {

// Thrown for unusable configuration or input files (metadata, calibration, capture file).
// The message names the file or field and what is wrong.
struct DriverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Counters of everything unusual a decoder met, plus the first message of each kind, so a
// caller can report "why were there no scans" without the decoder doing any logging itself.
class Diagnostics {
 public:
  // Adds one to `counter`; the first time a counter is raised its message is kept.
  void Count(const std::string& counter, std::string_view message = {}) {
    auto& n = counters_[counter];
    if (n++ == 0 && !message.empty() && messages_.size() < kMaxMessages) {
      messages_.push_back(counter + ": " + std::string(message));
    }
  }
  std::uint64_t Get(const std::string& counter) const {
    auto it = counters_.find(counter);
    return it == counters_.end() ? 0 : it->second;
  }
  const std::map<std::string, std::uint64_t>& counters() const { return counters_; }
  const std::vector<std::string>& messages() const { return messages_; }
  // "name=value name=value ..." for logs.
  std::string Summary() const {
    std::string s;
    for (const auto& [name, value] : counters_) {
      if (!s.empty()) s += ' ';
      s += name + '=' + std::to_string(value);
    }
    return s;
  }

 private:
  static constexpr std::size_t kMaxMessages = 64;
  std::map<std::string, std::uint64_t> counters_;
  std::vector<std::string> messages_;
};

}  // namespace dammloam::drivers
