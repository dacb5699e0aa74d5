#include "dds/security.hpp"

#include <ctime>
#include <mutex>
#include <string>

#include "dds/participant.hpp"
#include "security/security_folder.hpp"

namespace fleet::dds {

namespace {

struct SecuritySettings {
  std::string folder;
  std::string identity;
  security::ParticipantFiles files;
};

SecuritySettings& settings() {
  static SecuritySettings instance;
  return instance;
}

/// Cyclone's error and warning lines while a participant is created: the reason it refuses one.
struct CapturedLog {
  std::mutex mutex;
  std::string text;
};

void capture(void* target, const dds_log_data_t* data) {
  auto* log = static_cast<CapturedLog*>(target);
  const std::lock_guard<std::mutex> lock(log->mutex);
  std::string line(data->message, data->size);
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
  if (!line.empty()) log->text += (log->text.empty() ? "" : "; ") + line;
}

std::string file_uri(const std::string& path) {
  return "file:" + path;
}

}  // namespace

void use_security(const std::string& folder, const std::string& identity) {
  if (folder.empty()) {
    settings() = {};
    return;
  }
  const auto now = static_cast<std::int64_t>(std::time(nullptr));
  settings() = {folder, identity, security::participant_files(folder, identity, now)};
}

const std::string& security_identity() {
  return settings().identity;
}

const std::string& security_folder() {
  return settings().folder;
}

dds_entity_t create_participant(std::uint32_t domain) {
  const std::string where = "create DDS participant on domain " + std::to_string(domain);
  const SecuritySettings& s = settings();
  if (s.identity.empty()) return check(dds_create_participant(domain, nullptr, nullptr), where);
  dds_qos_t* qos = dds_create_qos();
  // The plugins Debian's libddsc ships, found by name on the library path.
  dds_qset_prop(qos, "dds.sec.auth.library.path", "dds_security_auth");
  dds_qset_prop(qos, "dds.sec.auth.library.init", "init_authentication");
  dds_qset_prop(qos, "dds.sec.auth.library.finalize", "finalize_authentication");
  dds_qset_prop(qos, "dds.sec.crypto.library.path", "dds_security_crypto");
  dds_qset_prop(qos, "dds.sec.crypto.library.init", "init_crypto");
  dds_qset_prop(qos, "dds.sec.crypto.library.finalize", "finalize_crypto");
  dds_qset_prop(qos, "dds.sec.access.library.path", "dds_security_ac");
  dds_qset_prop(qos, "dds.sec.access.library.init", "init_access_control");
  dds_qset_prop(qos, "dds.sec.access.library.finalize", "finalize_access_control");
  dds_qset_prop(qos, "dds.sec.auth.identity_ca", file_uri(s.files.identity_ca).c_str());
  dds_qset_prop(qos, "dds.sec.auth.identity_certificate", file_uri(s.files.certificate).c_str());
  dds_qset_prop(qos, "dds.sec.auth.private_key", file_uri(s.files.private_key).c_str());
  dds_qset_prop(qos, "dds.sec.access.permissions_ca", file_uri(s.files.permissions_ca).c_str());
  dds_qset_prop(qos, "dds.sec.access.governance", file_uri(s.files.governance).c_str());
  dds_qset_prop(qos, "dds.sec.access.permissions", file_uri(s.files.permissions).c_str());
  CapturedLog log;
  dds_set_log_sink(capture, &log);
  const dds_entity_t participant = dds_create_participant(domain, qos, nullptr);
  dds_set_log_sink(nullptr, nullptr);
  dds_delete_qos(qos);
  if (participant < 0) {
    throw DdsError(where + " as '" + s.identity + "' with the credentials of " + s.folder + ": " +
                   dds_strretcode(participant) + (log.text.empty() ? "" : " (" + log.text + ")"));
  }
  return participant;
}

std::string refusal_hint(dds_return_t rc) {
  if (rc != DDS_RETCODE_NOT_ALLOWED_BY_SECURITY || settings().identity.empty()) return "";
  return " (" + settings().files.permissions + " does not grant it to '" + settings().identity + "')";
}

}  // namespace fleet::dds
