#pragma once
// What the middleware drops before the application sees anything, for the readers and writers a
// MiddlewareWatch is given:
//   - readers: SAMPLE_LOST, SAMPLE_REJECTED and REQUESTED_INCOMPATIBLE_QOS, writers:
//     OFFERED_INCOMPATIBLE_QOS, polled with dds_get_*_status (each poll resets the change counts);
//     an incompatible QoS names the policy (last_policy_id). A remote type with the same name but
//     a layout Cyclone finds not assignable (both sides send XTypes type information) is such a
//     QoS mismatch too, policy type_consistency: the endpoints never match.
//   - samples Cyclone matched but could not deserialize (the writer sent no type information, as
//     Fast DDS 2.9 or a ROS 2 rmw does, and its layout differs): Cyclone 0.10.2 drops every one
//     with a "deserialization TOPIC/TYPE failed" warning and changes no status at all (sample
//     lost/rejected, requested incompatible QoS and inconsistent topic all stay 0). The only
//     observable trace is that log line: a process-wide Cyclone log sink (dds_set_log_sink)
//     catches it, forwards every Cyclone log line to stderr as before, and hands the failure to
//     the watch whose reader on that topic is matched with the sending writer.
#include <dds/dds.h>

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "services/dds/dds.hpp"

namespace dammloam::dds {

enum class DropKind {
  kSampleLost,                // reader: samples the writer sent that never arrived
  kSampleRejected,            // reader: samples refused for resource limits
  kRequestedIncompatibleQos,  // reader: a writer on the topic was not matched (QoS or type)
  kOfferedIncompatibleQos,    // writer: a reader on the topic was not matched (QoS or type)
  kUndeserializable,          // reader: matched, but the payload does not fit the type
};
// sample_lost, sample_rejected, requested_incompatible_qos, offered_incompatible_qos,
// undeserializable.
const char* Name(DropKind kind);

// The policy of a DDS_*_QOS_POLICY_ID in lower case (reliability, durability, ownership,
// type_consistency, ...); "policy N" for an id this Cyclone version does not define.
std::string QosPolicyName(std::uint32_t policy_id);

struct MiddlewareEvent {
  DropKind kind = DropKind::kSampleLost;
  std::string topic;
  // New since the previous poll: samples, or for incompatible QoS the matches Cyclone refused
  // (its total_count_change; one remote endpoint may be refused more than once, e.g. before and
  // after its type was resolved).
  std::uint64_t count = 0;
  // requested/offered incompatible QoS: the policy name; sample rejected: the limit
  // (samples_limit, ...); undeserializable: the writer's GUID (empty for a local writer).
  std::string detail;
  std::string type_name;    // undeserializable: the type Cyclone tried

  // "<kind>:<topic>" plus ":<policy>" for incompatible QoS: the key of a by-reason count.
  std::string Reason() const;
  // One line for a log and Status.last_error, naming the topic and, for QoS, the policy.
  std::string Describe() const;
};

class MiddlewareWatch {
 public:
  MiddlewareWatch();
  ~MiddlewareWatch();
  MiddlewareWatch(const MiddlewareWatch&) = delete;
  MiddlewareWatch& operator=(const MiddlewareWatch&) = delete;

  // The endpoints must outlive this watch's last Poll().
  void Watch(const ReaderBase& reader);
  void Watch(const WriterBase& writer);

  // What changed since the previous poll, at most one event per endpoint and kind (and per
  // writer for undeserializable samples). Call from one thread at a time.
  std::vector<MiddlewareEvent> Poll();

  struct Inbox;  // undeserializable samples reported by the log sink (middleware_watch.cpp)

 private:
  struct Endpoint {
    dds_entity_t handle;
    std::string topic;
    bool reader;
  };
  void PollReader(const Endpoint& endpoint, std::vector<MiddlewareEvent>& events) const;
  void PollWriter(const Endpoint& endpoint, std::vector<MiddlewareEvent>& events) const;
  void RememberMatchedWriters(bool always);
  void PollUndeserializable(std::vector<MiddlewareEvent>& events);

  std::vector<Endpoint> endpoints_;
  // Every writer ever matched with a watched reader (GUID text, as Cyclone logs it): a failure
  // logged for a writer matched with some other participant's reader is not ours.
  std::set<std::string> matched_writers_;
  std::shared_ptr<Inbox> inbox_;
};

// The GUID as Cyclone's log lines print it (PGUIDFMT: four hex words, "1106dc3:de850ac:...").
std::string LoggedGuid(const dds_guid_t& guid);

}  // namespace dammloam::dds
