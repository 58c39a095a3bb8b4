#include "services/dds/dds.hpp"

#include <cstdint>
#include <thread>

namespace dammloam::dds {

dds_entity_t Check(dds_entity_t rc, const std::string& what) {
  if (rc < 0) throw DdsError(what + ": " + dds_strretcode(rc));
  return rc;
}

Entity::~Entity() {
  if (handle_ > 0) dds_delete(handle_);
}

Entity& Entity::operator=(Entity&& other) noexcept {
  if (this != &other) {
    if (handle_ > 0) dds_delete(handle_);
    handle_ = std::exchange(other.handle_, 0);
  }
  return *this;
}

Qos::Qos(const TopicQos& topic_qos) : qos_(dds_create_qos()) {
  dds_qset_reliability(qos_, topic_qos.reliable ? DDS_RELIABILITY_RELIABLE
                                                : DDS_RELIABILITY_BEST_EFFORT,
                       DDS_SECS(1));
  if (topic_qos.depth > 0) {
    dds_qset_history(qos_, DDS_HISTORY_KEEP_LAST, topic_qos.depth);
  } else {
    dds_qset_history(qos_, DDS_HISTORY_KEEP_ALL, 0);
  }
  dds_qset_durability(qos_, topic_qos.transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL
                                                      : DDS_DURABILITY_VOLATILE);
  if (topic_qos.transient_local) {
    // What a late joiner receives follows the durability-service history (default keep-last
    // 1), not the writer's history: keep as many as the topic's depth.
    dds_qset_durability_service(qos_, 0, topic_qos.depth > 0 ? DDS_HISTORY_KEEP_LAST
                                                             : DDS_HISTORY_KEEP_ALL,
                                topic_qos.depth > 0 ? topic_qos.depth : 0,
                                DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  }
}

Qos::~Qos() { dds_delete_qos(qos_); }

Participant::Participant(dds_domainid_t domain)
    : Entity(Check(dds_create_participant(domain, nullptr, nullptr),
                   "creating a DDS participant on domain " + std::to_string(domain) +
                       " (check CYCLONEDDS_URI)")) {}

Topic::Topic(const Participant& participant, const dds_topic_descriptor_t& descriptor,
             const std::string& name, const TopicQos& qos)
    : Entity(Check(dds_create_topic(participant.handle(), &descriptor, name.c_str(),
                                    Qos(qos).get(), nullptr),
                   "creating topic '" + name + "'")),
      name_(name) {}

WriterBase::WriterBase(const Participant& participant, const Topic& topic, const TopicQos& qos)
    : Entity(Check(dds_create_writer(participant.handle(), topic.handle(), Qos(qos).get(), nullptr),
                   "creating a writer for '" + topic.name() + "'")),
      topic_name_(topic.name()) {}

int WriterBase::MatchedReaders() const {
  dds_publication_matched_status_t status{};
  Check(dds_get_publication_matched_status(handle(), &status), "publication matched status");
  return static_cast<int>(status.current_count);
}

bool WriterBase::WaitForReaders(int count, std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (MatchedReaders() < count) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

void WriterBase::WriteRaw(const void* sample, const char* topic_name) const {
  Check(dds_write(handle(), sample), std::string("writing to '") + topic_name + "'");
}

ReaderBase::ReaderBase(const Participant& participant, const Topic& topic, const TopicQos& qos)
    : Entity(Check(dds_create_reader(participant.handle(), topic.handle(), Qos(qos).get(), nullptr),
                   "creating a reader for '" + topic.name() + "'")),
      topic_name_(topic.name()) {}

int ReaderBase::MatchedWriters() const {
  dds_subscription_matched_status_t status{};
  Check(dds_get_subscription_matched_status(handle(), &status), "subscription matched status");
  return static_cast<int>(status.current_count);
}

std::string GuidText(const dds_guid_t& guid) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string text;
  for (const std::uint8_t byte : guid.v) {
    text += kHex[byte >> 4];
    text += kHex[byte & 0xF];
  }
  return text;
}

std::string ParticipantGuid(const Participant& participant) {
  dds_guid_t guid{};
  Check(dds_get_guid(participant.handle(), &guid), "participant GUID");
  return GuidText(guid);
}

std::string SenderParticipantGuid(const ReaderBase& reader, dds_instance_handle_t publication) {
  dds_builtintopic_endpoint_t* writer =
      dds_get_matched_publication_data(reader.handle(), publication);
  if (writer == nullptr) return "";
  std::string guid = GuidText(writer->participant_key);
  dds_builtintopic_free_endpoint(writer);
  return guid;
}

int ReaderBase::TakeLoans(void** samples, dds_sample_info_t* infos, int max) const {
  return Check(dds_take(handle(), samples, infos, static_cast<size_t>(max),
                        static_cast<uint32_t>(max)),
               "taking samples");
}

void ReaderBase::ReturnLoans(void** samples, int count) const {
  if (count > 0) dds_return_loan(handle(), samples, count);
}

WaitSet::WaitSet(const Participant& participant)
    : Entity(Check(dds_create_waitset(participant.handle()), "creating a waitset")) {
  // A waitset attached to itself triggers on dds_waitset_set_trigger(): that is Wake().
  Check(dds_waitset_attach(handle(), handle(), 0), "attaching the waitset to itself");
}

void WaitSet::Attach(const ReaderBase& reader) {
  Entity condition(Check(dds_create_readcondition(reader.handle(), DDS_ANY_STATE),
                         "creating a read condition"));
  Check(dds_waitset_attach(handle(), condition.handle(), 0), "attaching a reader to a waitset");
  conditions_.push_back(std::move(condition));
}

bool WaitSet::Wait(std::chrono::milliseconds timeout) const {
  const dds_return_t n = dds_waitset_wait(handle(), nullptr, 0, DDS_MSECS(timeout.count()));
  Check(n, "waiting on a waitset");
  return n > 0;
}

void WaitSet::Wake() const { dds_waitset_set_trigger(handle(), true); }

}  // namespace dammloam::dds
