#include "security/security_folder.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <ctime>
#include <filesystem>
#include <fstream>

#include "security/credentials.hpp"

namespace fleet::security {
namespace {

namespace fs = std::filesystem;

class SecurityFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("fleet-security-test-" + std::to_string(::getpid()) + "-" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string folder(const std::string& name) const { return (root_ / name).string(); }
  static std::int64_t now() { return static_cast<std::int64_t>(std::time(nullptr)); }
  /// The SecurityError participant_files throws, or "" when it throws none.
  static std::string refusal(const std::string& dir, const std::string& identity, std::int64_t at) {
    try {
      participant_files(dir, identity, at);
    } catch (const SecurityError& e) {
      return e.what();
    }
    return "";
  }
  fs::path root_;
};

TEST_F(SecurityFolder, EveryIdentityOfTheSiteGetsCredentialsThatCheckOut) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1", "fl-2"}), 30, false);
  for (const char* identity : {"server", "operator", "fl-1", "fl-2"}) {
    const ParticipantFiles files = participant_files(dir, identity, now());
    EXPECT_TRUE(fs::exists(files.certificate)) << identity;
    EXPECT_EQ(fs::status(files.private_key).permissions() & fs::perms::others_read, fs::perms::none) << identity;
  }
  const auto certificates = expiries(dir);
  ASSERT_EQ(certificates.size(), 7u);  // two authorities, four identities and the web view
  for (const Expiry& c : certificates) {
    EXPECT_NEAR(static_cast<double>(c.not_after - now()), 30.0 * 86400.0, 120.0) << c.file;
  }
}

TEST_F(SecurityFolder, ASiteWithVda5050VehiclesGetsABridgeIdentityForThemAlone) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1", "v1", "v2"}, {"v1", "v2"}), 30, false);
  EXPECT_NO_THROW(participant_files(dir, kVda5050Identity, now()));
  std::ifstream in(FolderLayout(dir).permissions_text(kVda5050Identity));
  const std::string permissions(std::istreambuf_iterator<char>(in), {});
  EXPECT_NE(permissions.find("<partition>robot.v1</partition>"), std::string::npos) << permissions;
  EXPECT_NE(permissions.find("<partition>robot.v2</partition>"), std::string::npos) << permissions;
  EXPECT_EQ(permissions.find("robot.fl-1"), std::string::npos) << permissions;
  EXPECT_FALSE(fs::exists(folder("plain")));
  init_folder(folder("plain"), site_identities({"fl-1"}), 30, false);
  EXPECT_FALSE(fs::exists(FolderLayout(folder("plain")).identity_dir(kVda5050Identity)));
}

TEST_F(SecurityFolder, TheWebViewGetsAnHttpsCertificateForItsNamesFromTheIdentityAuthority) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1"}), 30, false, {"fleet.plant.example", "10.0.0.5", "::1"});
  const FolderLayout files(dir);
  const auto text = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string certificate = text(files.web_certificate());
  EXPECT_TRUE(issued_by(certificate, text(files.identity_ca())));
  EXPECT_TRUE(key_matches(text(files.web_key()), certificate));
  EXPECT_EQ(fs::status(files.web_key()).permissions() & fs::perms::others_read, fs::perms::none);
  EXPECT_EQ(read_certificate(certificate, files.web_certificate()).subject, "O = Fleet, CN = fleet.plant.example");
  EXPECT_THROW(init_folder(dir, site_identities({"fl-1"}), 30, true, {"two words"}), SecurityError);
  EXPECT_THROW(init_folder(dir, site_identities({"fl-1"}), 30, true, {}), SecurityError);
}

TEST_F(SecurityFolder, AnExistingAuthorityIsKeptUnlessReplacingIsAsked) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1"}), 30, false);
  try {
    init_folder(dir, site_identities({"fl-1"}), 30, false);
    FAIL() << "a second init replaced the authority";
  } catch (const SecurityError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/ca/identity_ca.pem"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
  init_folder(dir, site_identities({"fl-1"}), 30, true);
  EXPECT_EQ(refusal(dir, "fl-1", now()), "");
}

TEST_F(SecurityFolder, AnExpiredCertificateIsRefusedNamingItsFile) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1"}), 1, false);
  const std::string why = refusal(dir, "fl-1", now() + 3 * 86400);
  EXPECT_NE(why.find("expired on"), std::string::npos) << why;
  EXPECT_NE(why.find(".pem"), std::string::npos) << why;
}

TEST_F(SecurityFolder, ACertificateOfAnotherAuthorityIsRefused) {
  const std::string ours = folder("ours");
  const std::string theirs = folder("theirs");
  init_folder(ours, site_identities({"fl-1"}), 30, false);
  init_folder(theirs, site_identities({"fl-1"}), 30, false);
  const FolderLayout a(ours), b(theirs);
  fs::copy_file(b.certificate("fl-1"), a.certificate("fl-1"), fs::copy_options::overwrite_existing);
  fs::copy_file(b.private_key("fl-1"), a.private_key("fl-1"), fs::copy_options::overwrite_existing);
  const std::string why = refusal(ours, "fl-1", now());
  EXPECT_NE(why.find(a.certificate("fl-1") + ": not issued by the identity authority"), std::string::npos) << why;
  // Permissions signed by the other folder's authority are refused as well.
  init_folder(ours, site_identities({"fl-1"}), 30, true);
  fs::copy_file(b.permissions("fl-1"), a.permissions("fl-1"), fs::copy_options::overwrite_existing);
  const std::string why_permissions = refusal(ours, "fl-1", now());
  EXPECT_NE(why_permissions.find(a.permissions("fl-1") + ": not signed by the permissions authority"),
            std::string::npos)
      << why_permissions;
}

TEST_F(SecurityFolder, AMissingOrAlteredFileIsNamed) {
  const std::string dir = folder("site");
  init_folder(dir, site_identities({"fl-1", "fl-2"}), 30, false);
  const FolderLayout files(dir);
  EXPECT_NE(refusal(dir, "fl-9", now()).find(files.identity_dir("fl-9") + ": missing"), std::string::npos);
  EXPECT_NE(refusal(folder("nowhere"), "fl-1", now()).find("no such security folder"), std::string::npos);
  fs::copy_file(files.private_key("fl-2"), files.private_key("fl-1"), fs::copy_options::overwrite_existing);
  EXPECT_NE(refusal(dir, "fl-1", now()).find(files.private_key("fl-1") + ": not the key of"), std::string::npos);
  std::ofstream(files.permissions("fl-2"), std::ios::app) << "tampered\n";
  {
    // Altering the signed text itself: the signature no longer matches.
    std::ifstream in(files.permissions("fl-2"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = text.find("robot.fl-2");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 10, "robot.fl-1");
    std::ofstream(files.permissions("fl-2"), std::ios::trunc) << text;
  }
  EXPECT_NE(refusal(dir, "fl-2", now()).find(files.permissions("fl-2") + ": not signed"), std::string::npos);
  fs::remove(files.certificate("fl-2"));
  EXPECT_NE(refusal(dir, "fl-2", now()).find(files.certificate("fl-2") + ": missing"), std::string::npos);
}

}  // namespace
}  // namespace fleet::security
