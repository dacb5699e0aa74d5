#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "security/access_documents.hpp"

namespace fleet::security {

/// One process's name on the domain and what it may do there.
struct Identity {
  std::string name;  ///< "server", "operator", kVda5050Identity or a robot's id
  Role role = Role::kRobot;
  std::vector<std::string> robots;  ///< the robot a kRobot speaks for, the vehicles of a kBridge
};

/// The identity of fleet-vda5050, the bridge to the VDA 5050 vehicles of a site.
inline constexpr const char* kVda5050Identity = "vda5050";

/// The identities of a site: the server, the operator (fleetctl), each robot, and when the site
/// has VDA 5050 vehicles (`vehicle_ids`), the bridge that speaks for them.
std::vector<Identity> site_identities(const std::vector<std::string>& robot_ids,
                                      const std::vector<std::string>& vehicle_ids = {});

/// The files of a security folder (made by `fleetctl security init`):
///
///     DIR/ca/identity_ca.pem, identity_ca_key.pem      signs every identity's certificate
///     DIR/ca/permissions_ca.pem, permissions_ca_key.pem signs the governance and permissions
///     DIR/governance.xml, governance.p7s
///     DIR/identities/NAME/certificate.pem, key.pem, permissions.xml, permissions.p7s
///     DIR/web/certificate.pem, key.pem                  the web view's HTTPS, by the identity authority
struct FolderLayout {
  explicit FolderLayout(std::string folder) : dir(std::move(folder)) {}
  std::string dir;
  std::string identity_ca() const { return dir + "/ca/identity_ca.pem"; }
  std::string identity_ca_key() const { return dir + "/ca/identity_ca_key.pem"; }
  std::string permissions_ca() const { return dir + "/ca/permissions_ca.pem"; }
  std::string permissions_ca_key() const { return dir + "/ca/permissions_ca_key.pem"; }
  std::string governance() const { return dir + "/governance.p7s"; }
  std::string governance_text() const { return dir + "/governance.xml"; }
  std::string identity_dir(const std::string& name) const { return dir + "/identities/" + name; }
  std::string certificate(const std::string& name) const { return identity_dir(name) + "/certificate.pem"; }
  std::string private_key(const std::string& name) const { return identity_dir(name) + "/key.pem"; }
  std::string permissions(const std::string& name) const { return identity_dir(name) + "/permissions.p7s"; }
  std::string permissions_text(const std::string& name) const { return identity_dir(name) + "/permissions.xml"; }
  std::string web_certificate() const { return dir + "/web/certificate.pem"; }
  std::string web_key() const { return dir + "/web/key.pem"; }
};

/// The names a web certificate is made for when none are given: this host over loopback.
std::vector<std::string> default_web_names();

/// Makes the two authorities, the governance, each identity's key, certificate and permissions,
/// and the web view's HTTPS certificate for `web_names`, all valid from now for `days`. An
/// existing authority is kept unless `replace` is set: SecurityError names it otherwise. Keys are
/// written readable by their owner alone. Returns the end of the permissions' validity (seconds
/// since 1970, UTC).
std::int64_t init_folder(const std::string& dir, const std::vector<Identity>& identities, int days, bool replace,
                         const std::vector<std::string>& web_names = default_web_names());

/// When a credential of the folder stops being valid.
struct Expiry {
  std::string file;
  std::string subject;
  std::int64_t not_after = 0;  ///< seconds since 1970 (UTC)
};

/// Every certificate of the folder with its end of validity, soonest first.
std::vector<Expiry> expiries(const std::string& dir);

/// The files a participant of `identity` presents, each checked at `now` (seconds since 1970):
/// present and readable, the certificate current, issued by the folder's identity authority and
/// matching the key, the governance and permissions signed by its permissions authority.
/// SecurityError names the file and what is wrong with it.
struct ParticipantFiles {
  std::string identity_ca, certificate, private_key, permissions_ca, governance, permissions;
};
ParticipantFiles participant_files(const std::string& dir, const std::string& identity, std::int64_t now);

/// `seconds` since 1970 as YYYY-MM-DDTHH:MM:SS (UTC).
std::string utc_time(std::int64_t seconds);

}  // namespace fleet::security
