#pragma once
// DDS Security of a participant (DdsTransport::Security): the files checked with OpenSSL before
// Fast DDS sees them (its own refusals say little: "Error creating participant"), and the
// participant properties that turn on Fast DDS's built-in plugins.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cobra/dds/dds_transport.hpp"

namespace cobra::dds::detail {

/// What the checks learnt about a participant's identity.
struct CheckedSecurity {
  DdsTransport::Security files;  ///< absolute paths; permissions_ca filled in (`ca` when not given)
  std::string subject;           ///< the certificate's subject, RFC 2253 ("CN=cobra host_a,O=cobra lab,C=CH")
};

/// Checks `security` for the participant `participant` (for messages): every file given but
/// `permissions_ca`, each readable and parsed; the identity CA and the certificate valid now, the
/// certificate issued by the CA, the key the certificate's; the governance and permissions
/// documents signed (S/MIME) by the permissions CA; the permissions granting the certificate's
/// subject. @throws core::Error "dds participant 'P': security_<file> '<path>': <what is wrong>".
CheckedSecurity checkSecurity(const DdsTransport::Security& security, const std::string& participant);

/// Fast DDS's participant properties (name, value) for checked files: PKI-DH, Access-Permissions,
/// AES-GCM-GMAC.
std::vector<std::pair<std::string, std::string>> securityProperties(const CheckedSecurity& checked);

/// True when two distinguished names (RFC 2253 text) have the same attributes, whatever their
/// order and the spaces around ',' and '=' (as Fast DDS compares a grant's subject_name).
bool sameDistinguishedName(const std::string& a, const std::string& b);

/// Fast DDS tells the access-control refusal of an authenticated remote participant (its
/// permissions not signed by this participant's permissions CA, or not granting the domain) only
/// in its log (category SECURITY: "Error validating remote permissions for <GUID> (<why>)"), not
/// through a listener. A log consumer (registered once per process, beside Fast DDS's own) hands
/// each such refusal to every watcher: `refused(remote GUID prefix text, why)`, on Fast DDS's
/// logging thread. Returns the watcher's id for unwatchRefusals.
using RefusalWatcher = std::function<void(const std::string& prefix, const std::string& why)>;
int watchRefusals(RefusalWatcher refused);
/// After it returns, the watcher is never called again.
void unwatchRefusals(int id) noexcept;

}  // namespace cobra::dds::detail
