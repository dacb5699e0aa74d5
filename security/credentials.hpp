#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace fleet::security {

/// A credential that cannot be made, read or trusted; the message names the file and the fault.
class SecurityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A certificate and its private key, both PEM.
struct KeyPair {
  std::string certificate;
  std::string private_key;
};

/// A self-signed certificate authority on an EC prime256v1 key (what Cyclone DDS accepts besides
/// RSA 2048), valid from now for `days`.
KeyPair make_authority(const std::string& common_name, int days);

/// A certificate for `identity` (subject CN=identity, O=Fleet) on a new EC prime256v1 key,
/// signed by `authority`, valid from now for `days`.
KeyPair issue_identity(const KeyPair& authority, const std::string& identity, int days);

/// A TLS server certificate for the web view on a new EC prime256v1 key, signed by `authority`,
/// valid from now for `days`: subject CN=names[0], a subjectAltName per name (an IP address or a
/// DNS name, as a browser checks it), extended key usage serverAuth. `names` must not be empty.
KeyPair issue_web_certificate(const KeyPair& authority, const std::vector<std::string>& names, int days);

/// `document` signed by `signer` as clear-text S/MIME, as `openssl smime -sign -text` writes it
/// (the form Cyclone DDS reads governance and permissions documents in).
std::string sign_document(const KeyPair& signer, const std::string& document);

/// What a certificate says of itself.
struct CertificateFacts {
  std::string subject;          ///< one line, e.g. "O=Fleet, CN=server"
  std::int64_t not_before = 0;  ///< seconds since 1970 (UTC)
  std::int64_t not_after = 0;
};

/// Reads a PEM certificate; `source` names it in errors.
CertificateFacts read_certificate(const std::string& pem, const std::string& source);

/// Whether `certificate` (PEM) carries a valid signature of `authority` (PEM).
bool issued_by(const std::string& certificate, const std::string& authority);

/// Whether the S/MIME document `smime` is signed by `authority` and unaltered.
bool signed_by(const std::string& smime, const std::string& authority);

/// Whether `private_key` (PEM) is the key of `certificate` (PEM).
bool key_matches(const std::string& private_key, const std::string& certificate);

}  // namespace fleet::security
