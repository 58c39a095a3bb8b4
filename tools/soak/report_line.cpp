#include "tools/soak/report_line.hpp"

#include <sstream>

namespace dammloam::soak {

std::string FormatSent(const SentSample& s) {
  std::ostringstream line;
  line << "sent " << s.scan << ' ' << s.kind << ' ' << s.stamp.sec << ' ' << s.stamp.nanosec
       << ' ' << s.due.count() << ' ' << s.sent.count() << '\n';
  return line.str();
}

std::optional<SentSample> ParseSent(const std::string& line) {
  std::istringstream in(line);
  std::string tag;
  SentSample s;
  long long due = 0, sent = 0;
  if (!(in >> tag >> s.scan >> s.kind >> s.stamp.sec >> s.stamp.nanosec >> due >> sent) ||
      tag != "sent") {
    return std::nullopt;
  }
  s.due = std::chrono::nanoseconds(due);
  s.sent = std::chrono::nanoseconds(sent);
  return s;
}

}  // namespace dammloam::soak
