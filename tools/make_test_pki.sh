#!/usr/bin/env bash
# Makes the lab's test public-key infrastructure in OUTDIR (bash + the openssl command line only):
#   ca.crt, ca.key              the test certificate authority (EC prime256v1, 10 years)
#   host_a.{crt,key}            identities of the two hosts of a split run (CN=cobra host_a, ...)
#   host_b.{crt,key}
#   noperm.{crt,key}            an identity signed by the test CA that no permissions file grants
#   rogue_ca.{crt,key}          ANOTHER certificate authority, and
#   rogue.{crt,key}             an identity it signed (CN=cobra host_b: the same name, wrong CA)
#   server.{crt,key}            a TLS server certificate for CN=localhost
#                               (subjectAltName DNS:localhost, IP:127.0.0.1), signed by the test CA
#   expired.{crt,key}           an identity of the test CA whose validity ended in 2021
# and, when the DDS security templates are found (dds/security/ beside this script's folder), the
# signed DDS Security documents (see dds/README.md, "Security"):
#   governance.p7s                 encrypt everything, refuse unauthenticated participants
#   permissions_host_a.p7s         what host_a may publish and subscribe (its own topics only)
#   permissions_host_b.p7s         the same for host_b
#   permissions_noperm.p7s         a grant for noperm's subject that allows no topic of a run
#   rogue_governance.p7s           the governance, and host_b's permissions for rogue's subject
#   rogue_permissions.p7s          (CN=cobra host_b), signed by the rogue CA: a complete setup
#                                  that the test CA's participants must refuse
#   forged_permissions.p7s         host_b's grants for noperm's subject, signed by the rogue CA
#                                  (noperm's self-made permissions, with rogue_governance.p7s)
#   broken_governance.p7s          a governance whose XML does not parse (line 4's <domain_rule>
#                                  closed by line 6's </domain_access_rules>), signed by the test CA
# Idempotent: does nothing when every file exists and every certificate but expired.crt is valid
# for at least another day (a test can call it each time). Keys are unencrypted: test use only.
# Usage: tools/make_test_pki.sh OUTDIR
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 OUTDIR" >&2; exit 2; }
out=$1
here=$(cd "$(dirname "$0")" && pwd)
templates="$here/../dds/security"
mkdir -p "$out"
cd "$out"
# One maker at a time per folder (tests running in parallel may each call this script).
exec 9>.lock
flock 9

CERTS=(ca host_a host_b noperm rogue_ca rogue server)
SIGNED=()
[ -d "$templates" ] && SIGNED=(governance permissions_host_a permissions_host_b permissions_noperm rogue_governance rogue_permissions
          forged_permissions broken_governance)

# True when everything is present and the certificates stay valid for a day (86400 s).
current() {
  local c f
  for c in "${CERTS[@]}"; do
    [ -s "$c.crt" ] && [ -s "$c.key" ] || return 1
    openssl x509 -in "$c.crt" -noout -checkend 86400 >/dev/null 2>&1 || return 1
  done
  [ -s expired.crt ] && [ -s expired.key ] || return 1
  for f in "${SIGNED[@]}"; do [ -s "$f.p7s" ] || return 1; done
  # The signed documents must be newer than their templates (an edited template is re-signed).
  if [ ${#SIGNED[@]} -gt 0 ]; then
    for f in "$templates"/*.xml; do [ governance.p7s -nt "$f" ] || return 1; done
  fi
  return 0
}
if current; then exit 0; fi

umask 077
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1.key" 2>/dev/null; }

# A self-signed certificate authority $1 with subject $2, 10 years.
make_ca() {
  key "$1"
  openssl req -new -x509 -key "$1.key" -out "$1.crt" -days 3650 -subj "$2" \
    -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,digitalSignature,keyCertSign,cRLSign" \
    -addext "subjectKeyIdentifier=hash"
}

# An end identity $1 with subject $2, signed by CA $3, 2 years; extensions file lines in $4.
make_identity() {
  key "$1"
  openssl req -new -key "$1.key" -out "$tmp/$1.csr" -subj "$2"
  printf '%s\n' "basicConstraints=CA:FALSE" "keyUsage=critical,digitalSignature,keyAgreement" \
    "${4:-}" >"$tmp/$1.ext"
  openssl x509 -req -in "$tmp/$1.csr" -CA "$3.crt" -CAkey "$3.key" -CAcreateserial \
    -CAserial "$tmp/$3.srl" -out "$1.crt" -days 730 -extfile "$tmp/$1.ext" 2>/dev/null
}

make_ca ca "/C=CH/O=cobra lab/CN=cobra test CA"
make_identity host_a "/C=CH/O=cobra lab/CN=cobra host_a" ca
make_identity host_b "/C=CH/O=cobra lab/CN=cobra host_b" ca
make_identity noperm "/C=CH/O=cobra lab/CN=cobra noperm" ca
make_ca rogue_ca "/C=CH/O=rogue lab/CN=rogue CA"
make_identity rogue "/C=CH/O=cobra lab/CN=cobra host_b" rogue_ca
make_identity server "/C=CH/O=cobra lab/CN=localhost" ca \
  "$(printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\nextendedKeyUsage=serverAuth')"

# The expired identity: `openssl x509 -req` (3.0) cannot set a past start date, `openssl ca` can
# (-startdate/-enddate), with a throw-away database.
key expired
openssl req -new -key expired.key -out "$tmp/expired.csr" -subj "/C=CH/O=cobra lab/CN=cobra expired"
: >"$tmp/index.txt"
cat >"$tmp/ca.cnf" <<CNF
[ca]
default_ca = test
[test]
database = $tmp/index.txt
new_certs_dir = $tmp
serial = $tmp/expired.srl
default_md = sha256
policy = anything
unique_subject = no
copy_extensions = none
[anything]
C = optional
O = optional
CN = supplied
[identity]
basicConstraints = CA:FALSE
keyUsage = critical,digitalSignature,keyAgreement
CNF
echo 1000 >"$tmp/expired.srl"
openssl ca -batch -config "$tmp/ca.cnf" -cert ca.crt -keyfile ca.key -in "$tmp/expired.csr" \
  -out expired.crt -startdate 20200101000000Z -enddate 20210101000000Z -extensions identity \
  -notext 2>/dev/null

# The DDS Security documents, S/MIME-signed by the test CA (the permissions CA is the test CA;
# its digitalSignature key usage lets it sign them: S/MIME verification checks it).
subject() { openssl x509 -in "$1.crt" -noout -subject -nameopt RFC2253 | sed 's/^subject=//'; }
sign() {  # sign <template> <output name> <subject of the grant> [<signing CA>] (@SUBJECT@ in the template)
  local signer=${4:-ca}
  sed "s|@SUBJECT@|$3|" "$templates/$1.xml" >"$tmp/$2.xml"
  openssl smime -sign -in "$tmp/$2.xml" -text -out "$2.p7s" -signer "$signer.crt" -inkey "$signer.key"
}
if [ ${#SIGNED[@]} -gt 0 ]; then
  sign governance governance ""
  sign permissions_host_a permissions_host_a "$(subject host_a)"
  sign permissions_host_b permissions_host_b "$(subject host_b)"
  sign permissions_none permissions_noperm "$(subject noperm)"
  sign governance rogue_governance "" rogue_ca
  sign permissions_host_b rogue_permissions "$(subject rogue)" rogue_ca
  sign permissions_host_b forged_permissions "$(subject noperm)" rogue_ca
  cat >"$tmp/broken_governance.xml" <<'XML'
<?xml version="1.0" encoding="UTF-8"?>
<dds>
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
  </domain_access_rules>
</dds>
XML
  openssl smime -sign -in "$tmp/broken_governance.xml" -text -out broken_governance.p7s -signer ca.crt -inkey ca.key
fi
chmod 644 ./*.crt ./*.p7s 2>/dev/null || true
