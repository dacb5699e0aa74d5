#pragma once

#include <dds/dds.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dds/qos.hpp"

namespace fleet::dds {

class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws DdsError naming `what` when `rc` is a negative DDS return code.
dds_return_t check(dds_return_t rc, const std::string& what);

/// Per-topic glue, specialised in dds/topics.hpp for each core/model type: its topic name, and how
/// it is written and taken. Only topics.cpp sees the IDL's C structs.
template <typename T>
struct TopicTraits;

/// Sample metadata a caller may care about.
struct SampleInfo {
  bool valid_data = true;  ///< false for instance-state changes (writer gone, disposed)
  bool alive = true;       ///< the instance still has a live writer
  std::int64_t source_timestamp_ns = 0;
  dds_instance_handle_t publication_handle = 0;  ///< the writer that sent it (writer_partitions)
};

/// The partitions of the remote writer `publication` matched by `reader`; empty when it writes in
/// the default partition, or is no longer matched.
std::vector<std::string> writer_partitions(dds_entity_t reader, dds_instance_handle_t publication);

/// A domain participant; owns every entity created through it.
class Participant {
 public:
  explicit Participant(std::uint32_t domain);
  /// A participant whose writers take ownership strength `ownership_strength` (of the server-owned
  /// topics, qos::server_owned: a server's orders::strength).
  Participant(std::uint32_t domain, std::int32_t ownership_strength) : Participant(domain) {
    ownership_strength_ = ownership_strength;
  }
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  dds_entity_t handle() const { return handle_; }
  std::uint32_t domain() const { return domain_; }
  /// The ownership strength of its writers; 0 by default.
  std::int32_t ownership_strength() const { return ownership_strength_; }

  /// The topic for T, created once per participant.
  template <typename T>
  dds_entity_t topic() {
    return topic_for(TopicTraits<T>::name, TopicTraits<T>::descriptor());
  }

 private:
  dds_entity_t topic_for(const char* name, const dds_topic_descriptor_t* descriptor);
  dds_entity_t handle_;
  std::uint32_t domain_;
  std::int32_t ownership_strength_ = 0;
  std::map<std::string, dds_entity_t> topics_;
};

/// A publisher (or subscriber) of `participant` in the one partition `partition`: its writers
/// (readers) match only readers (writers) in that partition, so samples meant for one robot go to
/// that robot alone, not to every reader of the topic.
dds_entity_t create_publisher_in(dds_entity_t participant, const std::string& partition);
dds_entity_t create_subscriber_in(dds_entity_t participant, const std::string& partition);
/// A subscriber in every one of `partitions`: its readers match writers in any of them.
dds_entity_t create_subscriber_in(dds_entity_t participant, const std::vector<std::string>& partitions);

/// Counts of matched remote endpoints.
std::uint32_t matched_readers(dds_entity_t writer);
std::uint32_t matched_writers(dds_entity_t reader);

template <typename T>
class Writer {
 public:
  Writer(Participant& participant, const Qos& qos)
      : handle_(check(dds_create_writer(participant.handle(), participant.template topic<T>(),
                                        with_strength(qos, participant).get(), nullptr),
                      std::string("create writer ") + TopicTraits<T>::name)) {}
  /// A writer in partition `partition` alone (create_publisher_in).
  Writer(Participant& participant, const Qos& qos, const std::string& partition)
      : owner_(create_publisher_in(participant.handle(), partition)),
        handle_(check(
            dds_create_writer(owner_, participant.template topic<T>(), with_strength(qos, participant).get(), nullptr),
            std::string("create writer ") + TopicTraits<T>::name + " in partition " + partition)) {}
  ~Writer() { dds_delete(owner_ != 0 ? owner_ : handle_); }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// False when the write failed (for example a reliable reader that stopped taking data).
  bool write(const T& value) { return TopicTraits<T>::write(handle_, value) >= 0; }
  /// The writer's ownership strength (the participant's when it was created).
  static Qos with_strength(const Qos& qos, const Participant& participant) {
    Qos own(qos);
    dds_qset_ownership_strength(own.get(), participant.ownership_strength());
    return own;
  }
  /// Forgets the instance keyed by `value` (its history leaves the writer); readers see it not alive.
  void unregister(const T& value) { TopicTraits<T>::unregister(handle_, value); }
  /// Marks the instance keyed by `value` as deleted for every reader.
  void dispose(const T& value) { TopicTraits<T>::dispose(handle_, value); }

  std::uint32_t matched() const { return matched_readers(handle_); }

  /// Waits until at least `count` readers are matched; volatile data written before a reader
  /// matches is never delivered to it.
  bool wait_for_readers(std::uint32_t count, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched() < count) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      dds_sleepfor(DDS_MSECS(10));
    }
    return true;
  }

  dds_entity_t handle() const { return handle_; }

 private:
  dds_entity_t owner_ = 0;  ///< the publisher of a partition writer, deleted with it
  dds_entity_t handle_;
};

/// One writer of T per partition, for data meant for one reader (a robot's grants in its own
/// partition). `open` creates a partition's writer ahead of its first sample: created at the first
/// write, the writer would still be matching its readers as that sample goes out.
template <typename T>
class PartitionWriters {
 public:
  PartitionWriters(Participant& participant, Qos qos) : participant_(participant), qos_(std::move(qos)) {}

  Writer<T>& open(const std::string& partition) {
    auto it = writers_.find(partition);
    if (it == writers_.end()) {
      it = writers_.emplace(partition, std::make_unique<Writer<T>>(participant_, qos_, partition)).first;
    }
    return *it->second;
  }
  bool write(const std::string& partition, const T& value) { return open(partition).write(value); }

 private:
  Participant& participant_;
  Qos qos_;
  std::map<std::string, std::unique_ptr<Writer<T>>> writers_;
};

template <typename T>
class Reader {
 public:
  using Callback = std::function<void(T&&, const SampleInfo&)>;

  Reader(Participant& participant, const Qos& qos)
      : handle_(check(dds_create_reader(participant.handle(), participant.template topic<T>(), qos.get(), nullptr),
                      std::string("create reader ") + TopicTraits<T>::name)) {}
  /// A reader in partition `partition` alone (create_subscriber_in).
  Reader(Participant& participant, const Qos& qos, const std::string& partition)
      : owner_(create_subscriber_in(participant.handle(), partition)),
        handle_(check(dds_create_reader(owner_, participant.template topic<T>(), qos.get(), nullptr),
                      std::string("create reader ") + TopicTraits<T>::name + " in partition " + partition)) {}
  /// A reader in each of `partitions` (create_subscriber_in).
  Reader(Participant& participant, const Qos& qos, const std::vector<std::string>& partitions)
      : owner_(create_subscriber_in(participant.handle(), partitions)),
        handle_(check(dds_create_reader(owner_, participant.template topic<T>(), qos.get(), nullptr),
                      std::string("create reader ") + TopicTraits<T>::name)) {}
  ~Reader() { dds_delete(owner_ != 0 ? owner_ : handle_); }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// Takes every available sample, calling `fn` for each. Returns how many were taken.
  int take(const Callback& fn) { return TopicTraits<T>::take(handle_, fn); }

  /// Takes only valid data samples.
  int take_data(const std::function<void(T&&)>& fn) {
    return take([&](T&& value, const SampleInfo& info) {
      if (info.valid_data) fn(std::move(value));
    });
  }

  std::uint32_t matched() const { return matched_writers(handle_); }
  dds_entity_t handle() const { return handle_; }

  /// The key of the instance whose requested deadline (a Qos with one) passed most recently,
  /// when one passed since the last call. Poll often: between two calls only the last is named.
  std::optional<T> deadline_missed() {
    dds_requested_deadline_missed_status_t status;
    if (dds_get_requested_deadline_missed_status(handle_, &status) != DDS_RETCODE_OK ||
        status.total_count_change == 0) {
      return std::nullopt;
    }
    T key;
    if (TopicTraits<T>::key_of(handle_, status.last_instance_handle, key) < 0) return std::nullopt;
    return key;
  }

 private:
  dds_entity_t owner_ = 0;  ///< the subscriber of a partition reader, deleted with it
  dds_entity_t handle_;
};

/// Blocks until one of the attached readers has data or the timeout passes.
class WaitSet {
 public:
  explicit WaitSet(Participant& participant);
  ~WaitSet();
  WaitSet(const WaitSet&) = delete;
  WaitSet& operator=(const WaitSet&) = delete;

  void attach(dds_entity_t reader);
  /// Returns the number of triggered conditions (0 on timeout).
  int wait(std::chrono::microseconds timeout);

 private:
  dds_entity_t handle_;
  std::vector<dds_entity_t> conditions_;
};

}  // namespace fleet::dds
