#include "security.hpp"

#include <fastdds/dds/log/Log.hpp>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <tinyxml2.h>  // Fast DDS's own XML parser (its CMake package links it)

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string_view>

#include "cobra/core/error.hpp"

namespace cobra::dds::detail {
namespace {

template <class T, void (*Free)(T*)>
struct Freer {
  void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Freer<BIO, BIO_free_all>>;
using X509Ptr = std::unique_ptr<X509, Freer<X509, X509_free>>;
using Key = std::unique_ptr<EVP_PKEY, Freer<EVP_PKEY, EVP_PKEY_free>>;
using Store = std::unique_ptr<X509_STORE, Freer<X509_STORE, X509_STORE_free>>;
using StoreContext = std::unique_ptr<X509_STORE_CTX, Freer<X509_STORE_CTX, X509_STORE_CTX_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, Freer<PKCS7, PKCS7_free>>;

/// One file of the security settings, for messages: "dds participant 'needle': security_ca '/x/ca.crt'".
struct File {
  std::string participant, property, path;
  std::string head() const { return "dds participant '" + participant + "': security_" + property + " '" + path + "'"; }
  [[noreturn]] void fail(const std::string& what) const { throw core::Error(head() + ": " + what); }
};

/// OpenSSL's last error as text ("" when none), clearing its queue.
std::string opensslError() {
  std::string out;
  while (const unsigned long e = ERR_get_error()) {
    char buffer[256];
    ERR_error_string_n(e, buffer, sizeof buffer);
    out = buffer;  // the last is the most specific
  }
  return out;
}

std::string readAll(const File& f) {
  std::error_code ec;
  if (!std::filesystem::exists(f.path, ec)) f.fail("no such file");
  if (std::filesystem::is_directory(f.path, ec)) f.fail("is a folder, expected a file");
  std::ifstream in(f.path, std::ios::binary);
  if (!in) f.fail(std::string("cannot read it (") + std::strerror(errno) + ")");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.empty()) f.fail("is empty");
  return text;
}

Bio memoryBio(const std::string& text) { return Bio(BIO_new_mem_buf(text.data(), static_cast<int>(text.size()))); }

std::string nameText(const X509_NAME* name) {
  Bio out(BIO_new(BIO_s_mem()));
  X509_NAME_print_ex(out.get(), name, 0, XN_FLAG_RFC2253 & ~ASN1_STRFLGS_ESC_MSB);
  char* data = nullptr;
  const long size = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<std::size_t>(size));
}

std::string timeText(const ASN1_TIME* time) {
  Bio out(BIO_new(BIO_s_mem()));
  ASN1_TIME_print(out.get(), time);
  char* data = nullptr;
  const long size = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<std::size_t>(size));
}

/// A PEM certificate, valid now. @throws naming the file: not one, expired, not yet valid.
X509Ptr certificate(const File& f) {
  const std::string text = readAll(f);
  Bio bio = memoryBio(text);
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!cert) f.fail("is not a PEM certificate (" + opensslError() + ")");
  const std::string subject = nameText(X509_get_subject_name(cert.get()));
  if (X509_cmp_current_time(X509_get0_notAfter(cert.get())) < 0)
    f.fail("the certificate '" + subject + "' expired on " + timeText(X509_get0_notAfter(cert.get())) +
           "; make it again (tools/make_test_pki.sh for a lab's test certificates)");
  if (X509_cmp_current_time(X509_get0_notBefore(cert.get())) > 0)
    f.fail("the certificate '" + subject + "' is not valid before " + timeText(X509_get0_notBefore(cert.get())));
  return cert;
}

Store storeOf(X509* ca) {
  Store store(X509_STORE_new());
  X509_STORE_add_cert(store.get(), ca);
  return store;
}

/// The signed document's XML. @throws naming the file: not S/MIME, not signed by the CA.
std::string signedDocument(const File& f, X509* signer_ca, const std::string& ca_path) {
  const std::string text = readAll(f);
  Bio bio = memoryBio(text);
  BIO* content = nullptr;
  Pkcs7 p7(SMIME_read_PKCS7(bio.get(), &content));
  Bio content_owner(content);
  if (!p7)
    f.fail("is not an S/MIME signed document (" + opensslError() +
           "): sign the XML with `openssl smime -sign -text -in F.xml -out F.p7s -signer CA.crt -inkey CA.key`");
  Store store = storeOf(signer_ca);
  Bio out(BIO_new(BIO_s_mem()));
  if (PKCS7_verify(p7.get(), nullptr, store.get(), content, out.get(), PKCS7_TEXT) != 1)
    f.fail("its signature does not verify with the permissions CA '" + ca_path + "' (" + opensslError() +
           "): sign it with that CA");
  char* data = nullptr;
  const long size = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<std::size_t>(size));
}

/// Fast DDS parses the signed documents with tinyxml2 and, when one does not parse, only fails to
/// create the participant. @throws naming the file, the line and tinyxml2's error.
void requireWellFormed(const File& f, const std::string& xml) {
  tinyxml2::XMLDocument document;
  if (document.Parse(xml.data(), xml.size()) == tinyxml2::XML_SUCCESS) return;
  // ErrorStr(): "Error=XML_ERROR_MISMATCHED_ELEMENT ErrorID=15 (0xf) Line number=4: XMLElement name=x"
  std::string detail = document.ErrorStr();
  const std::size_t colon = detail.find(": ");
  detail = colon == std::string::npos ? "" : ", " + detail.substr(colon + 2);
  f.fail("is signed but is not well-formed XML (line " + std::to_string(document.ErrorLineNum()) + ": " +
         document.ErrorName() + detail + "): correct the XML document and sign it again");
}

/// The text of every <tag>...</tag> in `xml`, trimmed.
std::vector<std::string> elements(const std::string& xml, const std::string& tag) {
  std::vector<std::string> out;
  const std::string open = "<" + tag + ">", close = "</" + tag + ">";
  for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at + 1)) {
    const std::size_t begin = at + open.size(), end = xml.find(close, begin);
    if (end == std::string::npos) break;
    std::string value = xml.substr(begin, end - begin);
    const auto first = value.find_first_not_of(" \t\r\n");
    out.push_back(first == std::string::npos ? "" : value.substr(first, value.find_last_not_of(" \t\r\n") - first + 1));
  }
  return out;
}

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(' ');
  return first == std::string::npos ? "" : s.substr(first, s.find_last_not_of(' ') - first + 1);
}

/// "CN=a, O=b" -> {"CN=a", "O=b"} sorted; ',' inside quotes or escaped does not split.
std::vector<std::string> attributes(const std::string& dn) {
  std::vector<std::string> out;
  std::string current;
  bool quoted = false;
  for (std::size_t i = 0; i < dn.size(); ++i) {
    const char c = dn[i];
    if (c == '\\' && i + 1 < dn.size()) {
      current += dn[++i];
      continue;
    }
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) out.push_back(std::exchange(current, {}));
    else current += c;
  }
  out.push_back(current);
  for (std::string& a : out) {
    const auto eq = a.find('=');
    a = eq == std::string::npos ? trimmed(a) : trimmed(a.substr(0, eq)) + "=" + trimmed(a.substr(eq + 1));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

bool sameDistinguishedName(const std::string& a, const std::string& b) { return attributes(a) == attributes(b); }

CheckedSecurity checkSecurity(const DdsTransport::Security& security, const std::string& participant) {
  CheckedSecurity checked;
  DdsTransport::Security& files = checked.files;
  files = security;
  if (files.permissions_ca.empty()) files.permissions_ca = files.ca;
  const std::pair<const char*, std::string*> all[] = {{"ca", &files.ca},
                                                      {"certificate", &files.certificate},
                                                      {"key", &files.key},
                                                      {"governance", &files.governance},
                                                      {"permissions", &files.permissions},
                                                      {"permissions_ca", &files.permissions_ca}};
  for (const auto& [name, path] : all) {
    if (path->empty())
      throw core::Error("dds participant '" + participant + "': security_" + name +
                        " is not given: DDS Security needs security_ca, security_certificate, security_key, "
                        "security_governance and security_permissions (security_permissions_ca: security_ca when "
                        "not given), or none of them");
    *path = std::filesystem::absolute(*path).lexically_normal().string();
  }
  const auto file = [&](const char* property, const std::string& path) { return File{participant, property, path}; };

  const X509Ptr ca = certificate(file("ca", files.ca));
  const File cert_file = file("certificate", files.certificate);
  const X509Ptr cert = certificate(cert_file);
  checked.subject = nameText(X509_get_subject_name(cert.get()));
  {
    Store store = storeOf(ca.get());
    StoreContext context(X509_STORE_CTX_new());
    X509_STORE_CTX_init(context.get(), store.get(), cert.get(), nullptr);
    if (X509_verify_cert(context.get()) != 1)
      cert_file.fail("the certificate '" + checked.subject + "' (issued by '" +
                     nameText(X509_get_issuer_name(cert.get())) + "') does not verify with the identity CA '" +
                     files.ca + "' (" + X509_verify_cert_error_string(X509_STORE_CTX_get_error(context.get())) + ")");
  }
  {
    const File key_file = file("key", files.key);
    const std::string text = readAll(key_file);
    Bio bio = memoryBio(text);
    Key key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
    if (!key) key_file.fail("is not an unencrypted PEM private key (" + opensslError() + ")");
    if (X509_check_private_key(cert.get(), key.get()) != 1) {
      opensslError();
      key_file.fail("is not the key of the certificate '" + files.certificate + "' ('" + checked.subject + "')");
    }
  }
  const X509Ptr permissions_ca =
      files.permissions_ca == files.ca ? X509Ptr(X509_dup(ca.get())) : certificate(file("permissions_ca", files.permissions_ca));
  const File governance_file = file("governance", files.governance);
  const std::string governance = signedDocument(governance_file, permissions_ca.get(), files.permissions_ca);
  requireWellFormed(governance_file, governance);
  if (governance.find("<domain_access_rules>") == std::string::npos)
    governance_file.fail("is signed but is no governance document (no <domain_access_rules>)");
  const File permissions_file = file("permissions", files.permissions);
  const std::string permissions = signedDocument(permissions_file, permissions_ca.get(), files.permissions_ca);
  requireWellFormed(permissions_file, permissions);
  const std::vector<std::string> subjects = elements(permissions, "subject_name");
  if (subjects.empty()) permissions_file.fail("is signed but grants no one (no <subject_name>)");
  if (std::none_of(subjects.begin(), subjects.end(),
                   [&](const std::string& s) { return sameDistinguishedName(s, checked.subject); })) {
    std::string grants;
    for (const std::string& s : subjects) grants += (grants.empty() ? "'" : ", '") + s + "'";
    permissions_file.fail("grants nothing to the certificate '" + files.certificate + "' (subject '" + checked.subject +
                          "'): its grants are for " + grants + "; use the permissions of this certificate's subject");
  }
  return checked;
}

std::vector<std::pair<std::string, std::string>> securityProperties(const CheckedSecurity& checked) {
  const DdsTransport::Security& f = checked.files;
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.", access = "dds.sec.access.builtin.Access-Permissions.";
  return {{"dds.sec.auth.plugin", "builtin.PKI-DH"},
          {auth + "identity_ca", "file://" + f.ca},
          {auth + "identity_certificate", "file://" + f.certificate},
          {auth + "private_key", "file://" + f.key},
          {"dds.sec.access.plugin", "builtin.Access-Permissions"},
          {access + "permissions_ca", "file://" + f.permissions_ca},
          {access + "governance", "file://" + f.governance},
          {access + "permissions", "file://" + f.permissions},
          {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"}};
}

namespace {

struct Watchers {
  std::mutex mutex;
  int next = 0;
  std::map<int, RefusalWatcher> all;
};
/// Never destroyed: Fast DDS's logging thread may consume an entry while the process's statics
/// are being destroyed.
Watchers& watchers() {
  static Watchers* const w = new Watchers;
  return *w;
}

/// Picks the remote participants' permission refusals out of Fast DDS's log.
class RefusalConsumer final : public eprosima::fastdds::dds::LogConsumer {
 public:
  void Consume(const eprosima::fastdds::dds::Log::Entry& entry) override {
    // No static object here: the logging thread may consume an entry while statics are destroyed.
    constexpr std::string_view head = "Error validating remote permissions for ";
    const std::string& m = entry.message;
    if (m.rfind(head, 0) != 0) return;
    const std::size_t guid_end = m.find(' ', head.size());
    if (guid_end == std::string::npos) return;
    const std::string guid = m.substr(head.size(), guid_end - head.size());
    const std::string prefix = guid.substr(0, guid.find('|'));
    // "(<why> (<Fast DDS's file>:<line>))." -> "<why>"
    std::string why = m.substr(guid_end + 1);
    if (!why.empty() && why.front() == '(') why.erase(0, 1);
    if (const std::size_t source = why.find(" (./"); source != std::string::npos) why.erase(source);
    std::lock_guard lock(watchers().mutex);
    for (const auto& [id, refused] : watchers().all) refused(prefix, why);
  }
};

}  // namespace

int watchRefusals(RefusalWatcher refused) {
  static std::once_flag registered;
  std::call_once(registered, [] {
    eprosima::fastdds::dds::Log::RegisterConsumer(std::make_unique<RefusalConsumer>());
  });
  std::lock_guard lock(watchers().mutex);
  const int id = watchers().next++;
  watchers().all.emplace(id, std::move(refused));
  return id;
}

void unwatchRefusals(int id) noexcept {
  std::lock_guard lock(watchers().mutex);
  watchers().all.erase(id);
}

}  // namespace cobra::dds::detail
