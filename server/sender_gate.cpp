#include "server/sender_gate.hpp"

#include "model/senders.hpp"

namespace fleet::server {

namespace {

/// Seconds between two lines of one warning about one writer.
constexpr double kWarningInterval = 10.0;
/// Seconds between two ServerInfo samples that carry new refusals.
constexpr double kChangeInterval = 1.0;

std::string listed(const std::vector<std::string>& partitions) {
  if (partitions.empty()) return "the default partition";
  std::string text = "partition";
  for (const std::string& p : partitions) text += " '" + p + "'";
  return text;
}

}  // namespace

SenderGate::SenderGate(bool secured, std::shared_ptr<spdlog::logger> log)
    : secured_(secured), log_(std::move(log)), limiter_(kWarningInterval) {}

double SenderGate::now_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool SenderGate::admit(dds_entity_t reader, const dds::SampleInfo& info, const std::string& robot_id,
                       const char* topic) {
  auto known = partitions_.find(info.publication_handle);
  if (known == partitions_.end()) {
    // No data and a writer never heard: nothing to judge it by (a refused writer is known).
    if (!info.valid_data) return true;
    known = partitions_.emplace(info.publication_handle, dds::writer_partitions(reader, info.publication_handle)).first;
  }
  const model::SenderVerdict verdict = model::judge_sender(known->second, robot_id, secured_);
  if (verdict == model::SenderVerdict::kAccepted) return true;
  ++refused_;
  changed_ = true;
  if (logged_.emplace(info.publication_handle, topic).second) {
    const std::string sender =
        std::string(topic) + " naming '" + robot_id + "' from a writer in " + listed(known->second);
    senders_.push_back(sender);
    log_->warn("refused {}: it {}; its samples are counted, not logged again", sender, model::to_string(verdict));
  }
  return false;
}

void SenderGate::warn(const dds::SampleInfo& info, const std::string& what, const std::string& message) {
  long held_back = 0;
  if (!limiter_.allow(std::to_string(info.publication_handle) + "/" + what, now_s(), held_back)) return;
  if (held_back > 0) {
    log_->warn("{} ({} more like it from this writer in the last {:.0f} s)", message, held_back, kWarningInterval);
  } else {
    log_->warn("{}", message);
  }
}

bool SenderGate::take_change() {
  if (!changed_ || now_s() - last_change_s_ < kChangeInterval) return false;
  changed_ = false;
  last_change_s_ = now_s();
  return true;
}

}  // namespace fleet::server
