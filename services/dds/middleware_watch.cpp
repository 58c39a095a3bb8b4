#include "services/dds/middleware_watch.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>
#include <tuple>
#include <utility>

namespace dammloam::dds {

// Filled by the log sink on Cyclone's receive threads, emptied by Poll().
struct MiddlewareWatch::Inbox {
  struct Key {
    std::string topic, type_name, writer;
    bool operator<(const Key& o) const {
      return std::tie(topic, type_name, writer) < std::tie(o.topic, o.type_name, o.writer);
    }
  };
  std::mutex mutex;
  std::set<std::string> topics;           // of the watched readers
  std::map<Key, std::uint64_t> failures;  // since the last poll
};

namespace {

// Every live watch's inbox. Leaked on purpose: Cyclone threads may log while statics are being
// destroyed at exit.
struct SinkRegistry {
  std::mutex mutex;
  std::vector<std::weak_ptr<MiddlewareWatch::Inbox>> inboxes;
};
SinkRegistry& Registry() {
  static SinkRegistry* registry = new SinkRegistry;
  return *registry;
}

struct UndeserializableLine {
  std::string topic, type_name, writer;
};

// Cyclone 0.10.2 (ddsi/q_receive.c, remote_make_sample):
//   data(application, vendor 1.16): 1106dc3:de850ac:6657ffb:103 #5: deserialization
//   TOPIC/TYPE failed (REASON)
// and for a local writer (ddsi/q_transmit.c): local: deserialization TOPIC/TYPE failed in topic
// type conversion. Topic names may contain '/' (ROS 2 "rt/points"), type names do not.
std::optional<UndeserializableLine> ParseUndeserializable(std::string_view line) {
  constexpr std::string_view kStart = "deserialization ";
  constexpr std::string_view kEnd = " failed";
  const std::size_t start = line.find(kStart);
  if (start == std::string_view::npos) return std::nullopt;
  const std::size_t names = start + kStart.size();
  const std::size_t end = line.find(kEnd, names);
  if (end == std::string_view::npos) return std::nullopt;
  const std::string_view topic_type = line.substr(names, end - names);
  const std::size_t slash = topic_type.rfind('/');
  if (slash == std::string_view::npos) return std::nullopt;
  UndeserializableLine parsed{std::string(topic_type.substr(0, slash)),
                              std::string(topic_type.substr(slash + 1)), ""};
  const std::size_t colon = line.find("): ");
  const std::size_t hash = line.find(" #", colon == std::string_view::npos ? 0 : colon);
  if (colon != std::string_view::npos && hash != std::string_view::npos && hash < start) {
    parsed.writer = std::string(line.substr(colon + 3, hash - colon - 3));
  }
  return parsed;
}

void LogSink(void*, const dds_log_data_t* data) {
  // What Cyclone's default sink did: the line on stderr.
  std::fwrite(data->message, 1, data->size, stderr);
  if (data->size == 0 || data->message[data->size - 1] != '\n') std::fputc('\n', stderr);
  if ((data->priority & DDS_LC_WARNING) == 0) return;
  const auto parsed = ParseUndeserializable(std::string_view(data->message, data->size));
  if (!parsed) return;
  SinkRegistry& registry = Registry();
  std::lock_guard registry_lock(registry.mutex);
  for (const auto& weak : registry.inboxes) {
    const std::shared_ptr<MiddlewareWatch::Inbox> inbox = weak.lock();
    if (!inbox) continue;
    std::lock_guard lock(inbox->mutex);
    if (inbox->topics.count(parsed->topic) == 0) continue;
    ++inbox->failures[{parsed->topic, parsed->type_name, parsed->writer}];
  }
}

void InstallLogSink() {
  static std::once_flag once;
  std::call_once(once, [] { dds_set_log_sink(&LogSink, nullptr); });
}

const char* RejectedName(dds_sample_rejected_status_kind kind) {
  switch (kind) {
    case DDS_NOT_REJECTED: return "not_rejected";
    case DDS_REJECTED_BY_INSTANCES_LIMIT: return "instances_limit";
    case DDS_REJECTED_BY_SAMPLES_LIMIT: return "samples_limit";
    case DDS_REJECTED_BY_SAMPLES_PER_INSTANCE_LIMIT: return "samples_per_instance_limit";
  }
  return "unknown_limit";
}

}  // namespace

const char* Name(DropKind kind) {
  switch (kind) {
    case DropKind::kSampleLost: return "sample_lost";
    case DropKind::kSampleRejected: return "sample_rejected";
    case DropKind::kRequestedIncompatibleQos: return "requested_incompatible_qos";
    case DropKind::kOfferedIncompatibleQos: return "offered_incompatible_qos";
    case DropKind::kUndeserializable: return "undeserializable";
  }
  return "?";
}

std::string QosPolicyName(std::uint32_t policy_id) {
  switch (static_cast<dds_qos_policy_id_t>(policy_id)) {
    case DDS_INVALID_QOS_POLICY_ID: return "invalid";
    case DDS_USERDATA_QOS_POLICY_ID: return "user_data";
    case DDS_DURABILITY_QOS_POLICY_ID: return "durability";
    case DDS_PRESENTATION_QOS_POLICY_ID: return "presentation";
    case DDS_DEADLINE_QOS_POLICY_ID: return "deadline";
    case DDS_LATENCYBUDGET_QOS_POLICY_ID: return "latency_budget";
    case DDS_OWNERSHIP_QOS_POLICY_ID: return "ownership";
    case DDS_OWNERSHIPSTRENGTH_QOS_POLICY_ID: return "ownership_strength";
    case DDS_LIVELINESS_QOS_POLICY_ID: return "liveliness";
    case DDS_TIMEBASEDFILTER_QOS_POLICY_ID: return "time_based_filter";
    case DDS_PARTITION_QOS_POLICY_ID: return "partition";
    case DDS_RELIABILITY_QOS_POLICY_ID: return "reliability";
    case DDS_DESTINATIONORDER_QOS_POLICY_ID: return "destination_order";
    case DDS_HISTORY_QOS_POLICY_ID: return "history";
    case DDS_RESOURCELIMITS_QOS_POLICY_ID: return "resource_limits";
    case DDS_ENTITYFACTORY_QOS_POLICY_ID: return "entity_factory";
    case DDS_WRITERDATALIFECYCLE_QOS_POLICY_ID: return "writer_data_lifecycle";
    case DDS_READERDATALIFECYCLE_QOS_POLICY_ID: return "reader_data_lifecycle";
    case DDS_TOPICDATA_QOS_POLICY_ID: return "topic_data";
    case DDS_GROUPDATA_QOS_POLICY_ID: return "group_data";
    case DDS_TRANSPORTPRIORITY_QOS_POLICY_ID: return "transport_priority";
    case DDS_LIFESPAN_QOS_POLICY_ID: return "lifespan";
    case DDS_DURABILITYSERVICE_QOS_POLICY_ID: return "durability_service";
    case DDS_PROPERTY_QOS_POLICY_ID: return "property";
    case DDS_TYPE_CONSISTENCY_ENFORCEMENT_QOS_POLICY_ID: return "type_consistency";
    case DDS_DATA_REPRESENTATION_QOS_POLICY_ID: return "data_representation";
  }
  return "policy " + std::to_string(policy_id);
}

std::string MiddlewareEvent::Reason() const {
  std::string reason = std::string(Name(kind)) + ":" + topic;
  if (kind == DropKind::kRequestedIncompatibleQos || kind == DropKind::kOfferedIncompatibleQos) {
    reason += ":" + detail;
  }
  return reason;
}

std::string MiddlewareEvent::Describe() const {
  const std::string n = std::to_string(count);
  const std::string where = "'" + topic + "'";
  const std::string type_hint =
      detail == "type_consistency"
          ? " (a type of the same name whose layout is not assignable to this one)"
          : "";
  switch (kind) {
    case DropKind::kSampleLost:
      return "DDS [sample_lost]: " + n + " sample(s) on " + where +
             " lost before they reached dammloamd's reader";
    case DropKind::kSampleRejected:
      return "DDS [sample_rejected]: " + n + " sample(s) on " + where +
             " rejected by dammloamd's reader (" + detail + ")";
    case DropKind::kRequestedIncompatibleQos:
      return "DDS [requested_incompatible_qos]: a writer on " + where +
             " not matched by dammloamd's reader: incompatible QoS policy " + detail + type_hint +
             " (" + n + " refused match(es))";
    case DropKind::kOfferedIncompatibleQos:
      return "DDS [offered_incompatible_qos]: a reader on " + where +
             " not matched by dammloamd's writer: incompatible QoS policy " + detail + type_hint +
             " (" + n + " refused match(es))";
    case DropKind::kUndeserializable:
      return "DDS [undeserializable]: " + n + " sample(s) on " + where + " from writer " +
             (detail.empty() ? std::string("(local)") : detail) +
             " dropped by Cyclone DDS: the payload does not deserialize as " + type_name +
             " (same type name, different layout)";
  }
  return "DDS: ?";
}

std::string LoggedGuid(const dds_guid_t& guid) {
  std::uint32_t words[4] = {};  // the GUID's bytes are in network order
  for (int i = 0; i < 16; ++i) words[i / 4] = (words[i / 4] << 8) | guid.v[i];
  char text[4 * 9];
  std::snprintf(text, sizeof(text), "%x:%x:%x:%x", static_cast<unsigned>(words[0]),
                static_cast<unsigned>(words[1]), static_cast<unsigned>(words[2]),
                static_cast<unsigned>(words[3]));
  return text;
}

MiddlewareWatch::MiddlewareWatch() : inbox_(std::make_shared<Inbox>()) {
  {
    SinkRegistry& registry = Registry();
    std::lock_guard lock(registry.mutex);
    auto& v = registry.inboxes;
    v.erase(std::remove_if(v.begin(), v.end(), [](const auto& w) { return w.expired(); }),
            v.end());
    v.push_back(inbox_);
  }
  InstallLogSink();  // outside the registry lock: it waits for Cyclone's threads
}

MiddlewareWatch::~MiddlewareWatch() {
  SinkRegistry& registry = Registry();
  std::lock_guard lock(registry.mutex);
  auto& v = registry.inboxes;
  v.erase(std::remove_if(v.begin(), v.end(),
                         [this](const auto& w) { return w.expired() || w.lock() == inbox_; }),
          v.end());
}

void MiddlewareWatch::Watch(const ReaderBase& reader) {
  endpoints_.push_back({reader.handle(), reader.topic_name(), true});
  std::lock_guard lock(inbox_->mutex);
  inbox_->topics.insert(reader.topic_name());
}

void MiddlewareWatch::Watch(const WriterBase& writer) {
  endpoints_.push_back({writer.handle(), writer.topic_name(), false});
}

std::vector<MiddlewareEvent> MiddlewareWatch::Poll() {
  std::vector<MiddlewareEvent> events;
  for (const Endpoint& endpoint : endpoints_) {
    if (endpoint.reader) {
      PollReader(endpoint, events);
    } else {
      PollWriter(endpoint, events);
    }
  }
  RememberMatchedWriters(false);
  PollUndeserializable(events);
  return events;
}

void MiddlewareWatch::PollReader(const Endpoint& e, std::vector<MiddlewareEvent>& events) const {
  dds_sample_lost_status_t lost{};
  if (dds_get_sample_lost_status(e.handle, &lost) == DDS_RETCODE_OK &&
      lost.total_count_change > 0) {
    events.push_back({DropKind::kSampleLost, e.topic,
                      static_cast<std::uint64_t>(lost.total_count_change), "", ""});
  }
  dds_sample_rejected_status_t rejected{};
  if (dds_get_sample_rejected_status(e.handle, &rejected) == DDS_RETCODE_OK &&
      rejected.total_count_change > 0) {
    events.push_back({DropKind::kSampleRejected, e.topic,
                      static_cast<std::uint64_t>(rejected.total_count_change),
                      RejectedName(rejected.last_reason), ""});
  }
  dds_requested_incompatible_qos_status_t qos{};
  if (dds_get_requested_incompatible_qos_status(e.handle, &qos) == DDS_RETCODE_OK &&
      qos.total_count_change > 0) {
    events.push_back({DropKind::kRequestedIncompatibleQos, e.topic,
                      static_cast<std::uint64_t>(qos.total_count_change),
                      QosPolicyName(qos.last_policy_id), ""});
  }
}

void MiddlewareWatch::PollWriter(const Endpoint& e, std::vector<MiddlewareEvent>& events) const {
  dds_offered_incompatible_qos_status_t qos{};
  if (dds_get_offered_incompatible_qos_status(e.handle, &qos) == DDS_RETCODE_OK &&
      qos.total_count_change > 0) {
    events.push_back({DropKind::kOfferedIncompatibleQos, e.topic,
                      static_cast<std::uint64_t>(qos.total_count_change),
                      QosPolicyName(qos.last_policy_id), ""});
  }
}

// Looks at the matched writers whenever a reader's matches changed (or when `always`), so a
// writer that has left again by the time its failures are polled is still known as ours.
void MiddlewareWatch::RememberMatchedWriters(bool always) {
  for (const Endpoint& e : endpoints_) {
    if (!e.reader) continue;
    dds_subscription_matched_status_t matched{};
    const bool changed = dds_get_subscription_matched_status(e.handle, &matched) ==
                             DDS_RETCODE_OK && matched.total_count_change > 0;
    if (!changed && !always) continue;
    std::vector<dds_instance_handle_t> handles(16);
    dds_return_t n = dds_get_matched_publications(e.handle, handles.data(), handles.size());
    if (n > static_cast<dds_return_t>(handles.size())) {
      handles.resize(static_cast<std::size_t>(n));
      n = dds_get_matched_publications(e.handle, handles.data(), handles.size());
    }
    const std::size_t count = n > 0 ? std::min(static_cast<std::size_t>(n), handles.size()) : 0;
    for (std::size_t i = 0; i < count; ++i) {
      dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(e.handle, handles[i]);
      if (writer == nullptr) continue;
      matched_writers_.insert(LoggedGuid(writer->key));
      dds_builtintopic_free_endpoint(writer);
    }
  }
}

void MiddlewareWatch::PollUndeserializable(std::vector<MiddlewareEvent>& events) {
  std::map<Inbox::Key, std::uint64_t> failures;
  {
    std::lock_guard lock(inbox_->mutex);
    failures.swap(inbox_->failures);
  }
  const bool unknown_writer = std::any_of(failures.begin(), failures.end(), [this](const auto& f) {
    return !f.first.writer.empty() && matched_writers_.count(f.first.writer) == 0;
  });
  if (unknown_writer) RememberMatchedWriters(true);
  for (const auto& [key, count] : failures) {
    // A remote writer matched with some other participant's reader in this process is not ours;
    // a local one (no GUID in the log line) cannot be told apart and counts for every watch.
    if (!key.writer.empty() && matched_writers_.count(key.writer) == 0) continue;
    events.push_back({DropKind::kUndeserializable, key.topic, count, key.writer, key.type_name});
  }
}

}  // namespace dammloam::dds
