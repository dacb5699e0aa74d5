#include "security/security_folder.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "security/credentials.hpp"

namespace fleet::security {

namespace fs = std::filesystem;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw SecurityError(path + ": " + (fs::exists(path) ? "cannot be read: " : "missing: ") + std::strerror(errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `text` to `path` with permission bits `mode` (a key: 0600), replacing what was there.
void write_text(const std::string& path, const std::string& text, mode_t mode) {
  fs::create_directories(fs::path(path).parent_path());
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, mode);
  if (fd < 0) throw SecurityError(path + ": cannot be written: " + std::strerror(errno));
  ::fchmod(fd, mode);
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw SecurityError(path + ": cannot be written: " + std::strerror(error));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) throw SecurityError(path + ": cannot be written: " + std::strerror(errno));
}

constexpr mode_t kPublic = 0644;
constexpr mode_t kSecret = 0600;

/// The authority kept in `certificate` and `key`, or a new one written there.
KeyPair authority(const std::string& certificate, const std::string& key, const std::string& name, int days,
                  bool replace) {
  if (!replace && fs::exists(certificate)) {
    throw SecurityError(certificate +
                        ": an authority is there already; pass --force to replace it (every credential it "
                        "signed stops being trusted)");
  }
  KeyPair made = make_authority(name, days);
  write_text(key, made.private_key, kSecret);
  write_text(certificate, made.certificate, kPublic);
  return made;
}

}  // namespace

std::string utc_time(std::int64_t seconds) {
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm parts{};
  gmtime_r(&t, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &parts);
  return text;
}

std::vector<Identity> site_identities(const std::vector<std::string>& robot_ids,
                                      const std::vector<std::string>& vehicle_ids) {
  std::vector<Identity> identities{{"server", Role::kServer, {}}, {"operator", Role::kOperator, {}}};
  for (const std::string& id : robot_ids) identities.push_back({id, Role::kRobot, {id}});
  if (!vehicle_ids.empty()) identities.push_back({kVda5050Identity, Role::kBridge, vehicle_ids});
  return identities;
}

std::vector<std::string> default_web_names() {
  return {"localhost", "127.0.0.1"};
}

std::int64_t init_folder(const std::string& dir, const std::vector<Identity>& identities, int days, bool replace,
                         const std::vector<std::string>& web_names) {
  const FolderLayout files(dir);
  const KeyPair identity_ca =
      authority(files.identity_ca(), files.identity_ca_key(), "Fleet identity authority", days, replace);
  const KeyPair permissions_ca =
      authority(files.permissions_ca(), files.permissions_ca_key(), "Fleet permissions authority", days, replace);
  const std::string governance = governance_document();
  write_text(files.governance_text(), governance, kPublic);
  write_text(files.governance(), sign_document(permissions_ca, governance), kPublic);
  const std::int64_t now = static_cast<std::int64_t>(std::time(nullptr));
  const std::string not_before = utc_time(now - 60);
  const std::int64_t until = now + static_cast<std::int64_t>(days) * 86400;
  const std::string not_after = utc_time(until);
  for (const Identity& identity : identities) {
    const KeyPair credentials = issue_identity(identity_ca, identity.name, days);
    write_text(files.private_key(identity.name), credentials.private_key, kSecret);
    write_text(files.certificate(identity.name), credentials.certificate, kPublic);
    const std::string permissions =
        permissions_document(identity.name, grants_of(identity.role, identity.robots), not_before, not_after);
    write_text(files.permissions_text(identity.name), permissions, kPublic);
    write_text(files.permissions(identity.name), sign_document(permissions_ca, permissions), kPublic);
  }
  const KeyPair web = issue_web_certificate(identity_ca, web_names, days);
  write_text(files.web_key(), web.private_key, kSecret);
  write_text(files.web_certificate(), web.certificate, kPublic);
  return until;
}

std::vector<Expiry> expiries(const std::string& dir) {
  const FolderLayout files(dir);
  std::vector<std::string> certificates{files.identity_ca(), files.permissions_ca()};
  const fs::path identities = fs::path(dir) / "identities";
  if (fs::is_directory(identities)) {
    for (const auto& entry : fs::directory_iterator(identities)) {
      certificates.push_back(files.certificate(entry.path().filename().string()));
    }
  }
  if (fs::exists(files.web_certificate())) certificates.push_back(files.web_certificate());
  std::vector<Expiry> out;
  for (const std::string& path : certificates) {
    const CertificateFacts facts = read_certificate(read_text(path), path);
    out.push_back({path, facts.subject, facts.not_after});
  }
  std::stable_sort(out.begin(), out.end(), [](const Expiry& a, const Expiry& b) { return a.not_after < b.not_after; });
  return out;
}

ParticipantFiles participant_files(const std::string& dir, const std::string& identity, std::int64_t now) {
  const FolderLayout files(dir);
  if (!fs::is_directory(dir))
    throw SecurityError(dir + ": no such security folder (make one: fleetctl security init " + dir + ")");
  if (!fs::is_directory(files.identity_dir(identity))) {
    throw SecurityError(files.identity_dir(identity) + ": missing: the folder holds no credentials for '" + identity +
                        "' (fleetctl security init makes them for the site's robots)");
  }
  const std::string identity_ca = read_text(files.identity_ca());
  const std::string permissions_ca = read_text(files.permissions_ca());
  const std::string certificate = read_text(files.certificate(identity));
  const std::string key = read_text(files.private_key(identity));
  const auto current = [&](const std::string& pem, const std::string& path) {
    const CertificateFacts facts = read_certificate(pem, path);
    if (now > facts.not_after) throw SecurityError(path + ": expired on " + utc_time(facts.not_after) + " UTC");
    if (now < facts.not_before) throw SecurityError(path + ": not valid before " + utc_time(facts.not_before) + " UTC");
  };
  current(identity_ca, files.identity_ca());
  current(permissions_ca, files.permissions_ca());
  current(certificate, files.certificate(identity));
  if (!issued_by(certificate, identity_ca)) {
    throw SecurityError(files.certificate(identity) + ": not issued by the identity authority " + files.identity_ca());
  }
  if (!key_matches(key, certificate)) {
    throw SecurityError(files.private_key(identity) + ": not the key of " + files.certificate(identity));
  }
  for (const std::string& path : {files.governance(), files.permissions(identity)}) {
    if (!signed_by(read_text(path), permissions_ca)) {
      throw SecurityError(path + ": not signed by the permissions authority " + files.permissions_ca());
    }
  }
  return {files.identity_ca(),    files.certificate(identity), files.private_key(identity),
          files.permissions_ca(), files.governance(),          files.permissions(identity)};
}

}  // namespace fleet::security
