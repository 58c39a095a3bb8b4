#include "tools/driver/dds_sink.hpp"

#include <chrono>
#include <stdexcept>

#include "services/dds/dds.hpp"
#include "services/dds/network_guard.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::driver {
namespace {

class DdsSink : public ScanSink {
 public:
  explicit DdsSink(const DdsOptions& o)
      : participant_(static_cast<dds_domainid_t>(o.domain)),
        topic_(participant_, dammloam_msg_PointCloud_desc,
               o.topic.empty() ? dds::TopicNames{}.points : o.topic, dds::PointsQos()),
        writer_(participant_, topic_, dds::PointsQos()),
        frame_id_(o.frame_id),
        wait_for_subscriber_s_(o.wait_for_subscriber_s),
        description_("DDS topic " + topic_.name() + " on domain " + std::to_string(o.domain)) {}

  void Consume(const Scan& scan) override {
    if (seq_ == 0 && wait_for_subscriber_s_ > 0.0) {
      // Volatile samples written before discovery completes are lost: let a reader match first.
      writer_.WaitForReaders(1, std::chrono::milliseconds(static_cast<long>(wait_for_subscriber_s_ * 1000)));
    }
    const dds::CloudMessage message = dds::ScanToCloud(scan, frame_id_, seq_++);
    const dds::CloudView view(message);
    writer_.Write(view.get());
  }
  std::string Describe() const override { return description_; }

 private:
  dds::Participant participant_;
  dds::Topic topic_;
  dds::Writer<dammloam_msg_PointCloud> writer_;
  std::string frame_id_;
  double wait_for_subscriber_s_;
  std::string description_;
  std::uint64_t seq_ = 0;
};

}  // namespace

bool DdsAvailable() { return true; }

std::unique_ptr<ScanSink> MakeDdsSink(const DdsOptions& o) {
  if (const std::string problem = dds::NetworkConfigProblem(o.allow_default_network); !problem.empty()) {
    throw std::runtime_error(problem);
  }
  return std::make_unique<DdsSink>(o);
}

}  // namespace dammloam::driver
