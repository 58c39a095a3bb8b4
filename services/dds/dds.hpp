#pragma once
// Small RAII wrappers over the Cyclone DDS C API (Cyclone 0.10 ships no C++ binding in Debian).
// Every entity is deleted with its owner object; errors throw DdsError naming the call.
#include <dds/dds.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dammloam::dds {

struct DdsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Returns rc when it is a valid entity/return code, throws DdsError("<what>: <reason>") otherwise.
dds_entity_t Check(dds_entity_t rc, const std::string& what);

// Owns one DDS entity handle; deleting it also deletes its children (readers of a participant...).
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity();
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept;
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  dds_entity_t handle() const { return handle_; }

 private:
  dds_entity_t handle_ = 0;
};

// The QoS of one topic, applied alike to its topic, writers and readers.
struct TopicQos {
  bool reliable = true;
  int depth = 1;                 // keep-last depth; <= 0 means keep-all
  bool transient_local = false;  // late joiners get the last `depth` samples
};

// RAII dds_qos_t built from a TopicQos.
class Qos {
 public:
  explicit Qos(const TopicQos& topic_qos);
  ~Qos();
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  const dds_qos_t* get() const { return qos_; }

 private:
  dds_qos_t* qos_;
};

class Participant : public Entity {
 public:
  explicit Participant(dds_domainid_t domain);
};

class Topic : public Entity {
 public:
  Topic(const Participant& participant, const dds_topic_descriptor_t& descriptor,
        const std::string& name, const TopicQos& qos);
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

class WriterBase : public Entity {
 public:
  WriterBase(const Participant& participant, const Topic& topic, const TopicQos& qos);
  const std::string& topic_name() const { return topic_name_; }
  int MatchedReaders() const;
  // Blocks until at least `count` readers matched; false on timeout.
  bool WaitForReaders(int count, std::chrono::milliseconds timeout) const;

 protected:
  void WriteRaw(const void* sample, const char* topic_name) const;
  std::string topic_name_;
};

template <typename T>
class Writer : public WriterBase {
 public:
  using WriterBase::WriterBase;
  // Serialises `sample` before returning: pointers inside it may point to caller storage.
  void Write(const T& sample) const { WriteRaw(&sample, topic_name_.c_str()); }
};

class ReaderBase : public Entity {
 public:
  ReaderBase(const Participant& participant, const Topic& topic, const TopicQos& qos);
  const std::string& topic_name() const { return topic_name_; }
  int MatchedWriters() const;

 protected:
  // Takes up to `max` loaned samples; returns how many; samples/infos filled.
  int TakeLoans(void** samples, dds_sample_info_t* infos, int max) const;
  void ReturnLoans(void** samples, int count) const;

 private:
  std::string topic_name_;
};

template <typename T>
class Reader : public ReaderBase {
 public:
  using ReaderBase::ReaderBase;

  // Calls on_sample(const T&, const dds_sample_info_t&) for every valid sample taken (zero
  // copy: the sample is only valid during the call). Returns the number of valid samples.
  template <typename F>
  int TakeEach(F&& on_sample, int max = 16) const {
    std::vector<void*> samples(static_cast<std::size_t>(max), nullptr);
    std::vector<dds_sample_info_t> infos(static_cast<std::size_t>(max));
    const int n = TakeLoans(samples.data(), infos.data(), max);
    struct LoanGuard {  // loans go back even if on_sample throws
      const Reader* self;
      void** samples;
      int n;
      ~LoanGuard() { self->ReturnLoans(samples, n); }
    } guard{this, samples.data(), n};
    int valid = 0;
    for (int i = 0; i < n; ++i) {
      if (!infos[static_cast<std::size_t>(i)].valid_data) continue;
      ++valid;
      on_sample(*static_cast<const T*>(samples[static_cast<std::size_t>(i)]),
                infos[static_cast<std::size_t>(i)]);
    }
    return valid;
  }
};

// 32 lower-case hex digits of a DDS GUID (participant prefix first).
std::string GuidText(const dds_guid_t& guid);
// The GUID of this participant.
std::string ParticipantGuid(const Participant& participant);
// The GUID of the participant whose writer sent a sample this reader took (sample info's
// publication_handle); empty when that writer is no longer matched.
std::string SenderParticipantGuid(const ReaderBase& reader, dds_instance_handle_t publication);

// Blocks a thread until data arrives on any attached reader, a timeout, or Wake().
class WaitSet : public Entity {
 public:
  explicit WaitSet(const Participant& participant);
  void Attach(const ReaderBase& reader);
  // True if something triggered (data or Wake), false on timeout.
  bool Wait(std::chrono::milliseconds timeout) const;
  // Thread-safe: makes every current and future Wait() return at once.
  void Wake() const;

 private:
  std::vector<Entity> conditions_;
};

}  // namespace dammloam::dds
