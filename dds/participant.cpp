#include "dds/participant.hpp"

#include "dds/qos.hpp"
#include "dds/security.hpp"

namespace fleet::dds {

dds_return_t check(dds_return_t rc, const std::string& what) {
  if (rc < 0) throw DdsError(what + ": " + dds_strretcode(rc) + refusal_hint(rc));
  return rc;
}

Participant::Participant(std::uint32_t domain) : handle_(create_participant(domain)), domain_(domain) {}

Participant::~Participant() {
  dds_delete(handle_);
}

dds_entity_t Participant::topic_for(const char* name, const dds_topic_descriptor_t* descriptor) {
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  // Readers and writers take the policies they do not set from their topic (Cyclone merges them
  // in): ownership is set once here for the topics the server owns.
  const Qos topic_qos = qos::server_owned(name) ? qos::server_owned_topic() : Qos();
  const dds_entity_t topic =
      check(dds_create_topic(handle_, descriptor, name, topic_qos.get(), nullptr), std::string("create topic ") + name);
  topics_.emplace(name, topic);
  return topic;
}

namespace {

dds_entity_t create_in(dds_entity_t participant, const std::vector<std::string>& partitions, bool publisher) {
  dds_qos_t* qos = dds_create_qos();
  std::vector<const char*> names;
  for (const std::string& partition : partitions) names.push_back(partition.c_str());
  dds_qset_partition(qos, static_cast<uint32_t>(names.size()), names.data());
  const dds_entity_t entity =
      publisher ? dds_create_publisher(participant, qos, nullptr) : dds_create_subscriber(participant, qos, nullptr);
  dds_delete_qos(qos);
  std::string listed;
  for (const std::string& partition : partitions) listed += (listed.empty() ? "" : ", ") + partition;
  return check(entity, std::string(publisher ? "create publisher" : "create subscriber") + " in partition " + listed);
}

}  // namespace

dds_entity_t create_publisher_in(dds_entity_t participant, const std::string& partition) {
  return create_in(participant, {partition}, true);
}

dds_entity_t create_subscriber_in(dds_entity_t participant, const std::string& partition) {
  return create_in(participant, {partition}, false);
}

dds_entity_t create_subscriber_in(dds_entity_t participant, const std::vector<std::string>& partitions) {
  return create_in(participant, partitions, false);
}

std::uint32_t matched_readers(dds_entity_t writer) {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(writer, &status) < 0) return 0;
  return status.current_count;
}

std::uint32_t matched_writers(dds_entity_t reader) {
  dds_subscription_matched_status_t status{};
  if (dds_get_subscription_matched_status(reader, &status) < 0) return 0;
  return status.current_count;
}

std::vector<std::string> writer_partitions(dds_entity_t reader, dds_instance_handle_t publication) {
  std::vector<std::string> partitions;
  dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(reader, publication);
  if (writer == nullptr) return partitions;
  uint32_t count = 0;
  char** names = nullptr;
  if (writer->qos != nullptr && dds_qget_partition(writer->qos, &count, &names)) {
    for (uint32_t i = 0; i < count; ++i) {
      partitions.emplace_back(names[i]);
      dds_free(names[i]);
    }
    dds_free(names);
  }
  dds_builtintopic_free_endpoint(writer);
  return partitions;
}

WaitSet::WaitSet(Participant& participant)
    : handle_(check(dds_create_waitset(participant.handle()), "create waitset")) {}

WaitSet::~WaitSet() {
  for (dds_entity_t c : conditions_) dds_delete(c);
  dds_delete(handle_);
}

void WaitSet::attach(dds_entity_t reader) {
  const dds_entity_t condition = check(dds_create_readcondition(reader, DDS_ANY_STATE), "create read condition");
  conditions_.push_back(condition);
  check(dds_waitset_attach(handle_, condition, condition), "attach to waitset");
}

int WaitSet::wait(std::chrono::microseconds timeout) {
  return dds_waitset_wait(handle_, nullptr, 0, DDS_USECS(timeout.count()));
}

}  // namespace fleet::dds
