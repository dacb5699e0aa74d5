#include "security/credentials.hpp"

#include <arpa/inet.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <ctime>
#include <functional>
#include <memory>

namespace fleet::security {

namespace {

template <typename T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Store = std::unique_ptr<X509_STORE, Deleter<X509_STORE, X509_STORE_free>>;
using StoreContext = std::unique_ptr<X509_STORE_CTX, Deleter<X509_STORE_CTX, X509_STORE_CTX_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, Deleter<PKCS7, PKCS7_free>>;

/// OpenSSL's own reason for the last failure, for a message.
std::string openssl_reason() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "no reason given";
  char text[256];
  ERR_error_string_n(code, text, sizeof text);
  return text;
}

[[noreturn]] void fail(const std::string& what) {
  throw SecurityError(what + ": " + openssl_reason());
}

Bio memory_of(const std::string& text) {
  Bio bio(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  if (!bio) fail("cannot read from memory");
  return bio;
}

std::string text_of(BIO* bio) {
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  return std::string(data, static_cast<std::size_t>(size));
}

Key new_key() {
  Key key(EVP_EC_gen("P-256"));
  if (!key) fail("cannot make an EC prime256v1 key");
  return key;
}

Key parse_key(const std::string& pem) {
  Bio in = memory_of(pem);
  return Key(PEM_read_bio_PrivateKey(in.get(), nullptr, nullptr, nullptr));
}

Cert parse_certificate(const std::string& pem) {
  Bio in = memory_of(pem);
  return Cert(PEM_read_bio_X509(in.get(), nullptr, nullptr, nullptr));
}

std::string pem_of(X509* cert) {
  Bio out(BIO_new(BIO_s_mem()));
  if (!out || PEM_write_bio_X509(out.get(), cert) != 1) fail("cannot write a certificate");
  return text_of(out.get());
}

std::string pem_of(EVP_PKEY* key) {
  Bio out(BIO_new(BIO_s_mem()));
  if (!out || PEM_write_bio_PrivateKey(out.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1) {
    fail("cannot write a private key");
  }
  return text_of(out.get());
}

void add_extension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX context;
  X509V3_set_ctx_nodb(&context);
  X509V3_set_ctx(&context, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* extension = X509V3_EXT_conf_nid(nullptr, &context, nid, value);
  if (extension == nullptr) fail(std::string("cannot make certificate extension ") + OBJ_nid2sn(nid));
  X509_add_ext(cert, extension, -1);
  X509_EXTENSION_free(extension);
}

/// A certificate for `subject_cn` on `key`, valid from a minute ago (clocks of two hosts differ a
/// little) for `days`; issued by `issuer` (itself when null).
Cert new_certificate(const std::string& subject_cn, EVP_PKEY* key, X509* issuer, int days) {
  Cert cert(X509_new());
  if (!cert) fail("cannot make a certificate");
  X509_set_version(cert.get(), 2);  // X.509 v3: it carries extensions
  std::uint64_t serial = 0;
  if (RAND_bytes(reinterpret_cast<unsigned char*>(&serial), sizeof serial) != 1) fail("no random serial number");
  ASN1_INTEGER_set_uint64(X509_get_serialNumber(cert.get()), serial >> 1);
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), -60);
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), static_cast<long>(days) * 86400L);
  X509_NAME* name = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC, reinterpret_cast<const unsigned char*>("Fleet"), -1, -1, 0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC, reinterpret_cast<const unsigned char*>(subject_cn.c_str()), -1,
                             -1, 0);
  X509_set_issuer_name(cert.get(), issuer != nullptr ? X509_get_subject_name(issuer) : name);
  X509_set_pubkey(cert.get(), key);
  X509* signer = issuer != nullptr ? issuer : cert.get();
  // An authority carries no key usage: its key signs certificates and the S/MIME documents alike.
  add_extension(cert.get(), signer, NID_basic_constraints,
                issuer != nullptr ? "critical,CA:FALSE" : "critical,CA:TRUE");
  add_extension(cert.get(), signer, NID_subject_key_identifier, "hash");
  return cert;
}

std::int64_t seconds_of(const ASN1_TIME* time, const std::string& source) {
  std::tm parts{};
  if (ASN1_TIME_to_tm(time, &parts) != 1) throw SecurityError(source + ": unreadable validity date");
  return static_cast<std::int64_t>(timegm(&parts));
}

}  // namespace

KeyPair make_authority(const std::string& common_name, int days) {
  Key key = new_key();
  Cert cert = new_certificate(common_name, key.get(), nullptr, days);
  if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) fail("cannot sign the authority " + common_name);
  return {pem_of(cert.get()), pem_of(key.get())};
}

namespace {

/// A certificate for `subject_cn` on a new key, signed by `authority`, with the extensions
/// `extend` adds (given the new certificate and its issuer).
KeyPair issue_leaf(const KeyPair& authority, const std::string& subject_cn, int days,
                   const std::function<void(X509*, X509*)>& extend) {
  Cert issuer = parse_certificate(authority.certificate);
  Key issuer_key = parse_key(authority.private_key);
  if (!issuer || !issuer_key) fail("cannot read the identity authority");
  Key key = new_key();
  Cert cert = new_certificate(subject_cn, key.get(), issuer.get(), days);
  extend(cert.get(), issuer.get());
  if (X509_sign(cert.get(), issuer_key.get(), EVP_sha256()) == 0) fail("cannot sign the certificate of " + subject_cn);
  return {pem_of(cert.get()), pem_of(key.get())};
}

}  // namespace

KeyPair issue_identity(const KeyPair& authority, const std::string& identity, int days) {
  return issue_leaf(authority, identity, days, [](X509*, X509*) {});
}

KeyPair issue_web_certificate(const KeyPair& authority, const std::vector<std::string>& names, int days) {
  if (names.empty()) throw SecurityError("a web certificate needs at least one host name or address");
  std::string alt_names;
  for (const std::string& name : names) {
    unsigned char address[16];
    const bool is_address =
        inet_pton(AF_INET, name.c_str(), address) == 1 || inet_pton(AF_INET6, name.c_str(), address) == 1;
    if (name.empty() || (!is_address && name.find_first_of(",: \t") != std::string::npos)) {
      throw SecurityError("'" + name + "' is neither a host name nor an address, for a web certificate");
    }
    if (!alt_names.empty()) alt_names += ',';
    alt_names += is_address ? "IP:" : "DNS:";
    alt_names += name;
  }
  return issue_leaf(authority, names.front(), days, [&](X509* cert, X509* issuer) {
    add_extension(cert, issuer, NID_subject_alt_name, alt_names.c_str());
    add_extension(cert, issuer, NID_ext_key_usage, "serverAuth");
    add_extension(cert, issuer, NID_key_usage, "critical,digitalSignature,keyAgreement");
  });
}

std::string sign_document(const KeyPair& signer, const std::string& document) {
  Cert cert = parse_certificate(signer.certificate);
  Key key = parse_key(signer.private_key);
  if (!cert || !key) fail("cannot read the permissions authority");
  constexpr int kFlags = PKCS7_DETACHED | PKCS7_TEXT;
  Bio content = memory_of(document);
  Pkcs7 signature(PKCS7_sign(cert.get(), key.get(), nullptr, content.get(), kFlags));
  if (!signature) fail("cannot sign a document");
  Bio again = memory_of(document);
  Bio out(BIO_new(BIO_s_mem()));
  if (!out || SMIME_write_PKCS7(out.get(), signature.get(), again.get(), kFlags) != 1) {
    fail("cannot write a signed document");
  }
  return text_of(out.get());
}

CertificateFacts read_certificate(const std::string& pem, const std::string& source) {
  Cert cert = parse_certificate(pem);
  if (!cert) throw SecurityError(source + ": not a PEM certificate (" + openssl_reason() + ")");
  CertificateFacts facts;
  Bio out(BIO_new(BIO_s_mem()));
  X509_NAME_print_ex(out.get(), X509_get_subject_name(cert.get()), 0, XN_FLAG_ONELINE);
  facts.subject = text_of(out.get());
  facts.not_before = seconds_of(X509_get0_notBefore(cert.get()), source);
  facts.not_after = seconds_of(X509_get0_notAfter(cert.get()), source);
  return facts;
}

bool issued_by(const std::string& certificate, const std::string& authority) {
  Cert cert = parse_certificate(certificate);
  Cert ca = parse_certificate(authority);
  if (!cert || !ca) {
    ERR_clear_error();
    return false;
  }
  EVP_PKEY* ca_key = X509_get0_pubkey(ca.get());
  const bool ok = ca_key != nullptr && X509_verify(cert.get(), ca_key) == 1 &&
                  X509_NAME_cmp(X509_get_issuer_name(cert.get()), X509_get_subject_name(ca.get())) == 0;
  ERR_clear_error();
  return ok;
}

bool signed_by(const std::string& smime, const std::string& authority) {
  Cert ca = parse_certificate(authority);
  Bio in = memory_of(smime);
  BIO* content_raw = nullptr;
  Pkcs7 signature(SMIME_read_PKCS7(in.get(), &content_raw));
  Bio content(content_raw);
  Store store(X509_STORE_new());
  if (!ca || !signature || !store || X509_STORE_add_cert(store.get(), ca.get()) != 1) {
    ERR_clear_error();
    return false;
  }
  // The signer is the authority itself, so its chain is the one certificate in the store; the
  // check of its purpose is skipped as Cyclone DDS skips it.
  const bool ok =
      PKCS7_verify(signature.get(), nullptr, store.get(), content.get(), nullptr, PKCS7_TEXT | PKCS7_NOVERIFY) == 1;
  ERR_clear_error();
  if (!ok) return false;
  // NOVERIFY skips the chain: the signer must be the authority itself.
  STACK_OF(X509)* signers = PKCS7_get0_signers(signature.get(), nullptr, 0);
  const bool by_authority =
      signers != nullptr && sk_X509_num(signers) == 1 && X509_cmp(sk_X509_value(signers, 0), ca.get()) == 0;
  sk_X509_free(signers);
  ERR_clear_error();
  return by_authority;
}

bool key_matches(const std::string& private_key, const std::string& certificate) {
  Key key = parse_key(private_key);
  Cert cert = parse_certificate(certificate);
  const bool ok = key && cert && X509_check_private_key(cert.get(), key.get()) == 1;
  ERR_clear_error();
  return ok;
}

}  // namespace fleet::security
