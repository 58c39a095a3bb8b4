#include "tools/driver/packet_source.hpp"

#include <thread>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/udp_receiver.hpp"

namespace dammloam::driver {
namespace {

using Clock = std::chrono::steady_clock;

class PcapSource : public PacketSource {
 public:
  PcapSource(const std::filesystem::path& file, std::uint16_t port, double rate)
      : reader_(file, drivers::PcapFilter{port}), file_(file), rate_(rate) {}

  bool Next(drivers::UdpDatagram& out, const std::atomic<bool>& stop) override {
    if (stop || !reader_.Next(out)) return false;
    if (rate_ > 0.0) Pace(out.capture_time, stop);
    return true;
  }
  const drivers::Diagnostics* diagnostics() const override { return &reader_.diagnostics(); }
  std::string Describe() const override { return "capture " + file_.string(); }

 private:
  // Sleeps until the packet's recorded time, scaled by the rate, has come.
  void Pace(double capture_time, const std::atomic<bool>& stop) {
    if (!first_capture_) {
      first_capture_ = capture_time;
      wall_start_ = Clock::now();
      return;
    }
    const auto due = wall_start_ + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>((capture_time - *first_capture_) / rate_));
    while (!stop && Clock::now() < due) {
      std::this_thread::sleep_until(std::min(due, Clock::now() + std::chrono::milliseconds(50)));
    }
  }

  drivers::PcapReader reader_;
  std::filesystem::path file_;
  double rate_;
  std::optional<double> first_capture_;
  Clock::time_point wall_start_;
};

class LiveSource : public PacketSource {
 public:
  LiveSource(std::uint16_t port, const std::string& address, double idle_timeout_s)
      : receiver_(port, address), idle_timeout_s_(idle_timeout_s), last_data_(Clock::now()) {}

  bool Next(drivers::UdpDatagram& out, const std::atomic<bool>& stop) override {
    while (!stop) {
      if (receiver_.Receive(out, std::chrono::milliseconds(100))) {
        last_data_ = Clock::now();
        return true;
      }
      if (idle_timeout_s_ > 0.0 &&
          std::chrono::duration<double>(Clock::now() - last_data_).count() > idle_timeout_s_) {
        return false;
      }
    }
    return false;
  }
  std::string Describe() const override { return "UDP port " + std::to_string(receiver_.port()); }

 private:
  drivers::UdpReceiver receiver_;
  double idle_timeout_s_;
  Clock::time_point last_data_;
};

}  // namespace

std::unique_ptr<PacketSource> MakeSource(const SourceOptions& o) {
  if (o.pcap) return std::make_unique<PcapSource>(*o.pcap, o.sensor_port, o.rate);
  return std::make_unique<LiveSource>(o.udp_port.value_or(o.sensor_port), o.bind_address, o.idle_timeout_s);
}

}  // namespace dammloam::driver
