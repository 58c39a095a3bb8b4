#!/bin/sh
# Creates a DDS Security PKI for dammloam in OUT_DIR (default ./dammloam-pki):
#   identity_ca.pem (+ _key)     signs the participants' identity certificates
#   permissions_ca.pem (+ _key)  signs governance.p7s and permissions.p7s
#   NAME/cert.pem, NAME/key.pem  one identity per NAME (CN=NAME,O=dammloam), unencrypted key
#   governance.p7s, permissions.p7s  governance.xml and permissions.xml signed (S/MIME)
# usage: make-pki.sh [-o OUT_DIR] [-d DAYS] [NAME...]   (names default to the four subjects of
# permissions.xml). Keep the *_ca_key.pem files off the robot; copy the rest (each process needs
# only its own NAME directory). Re-running reuses existing CAs and keys, re-signs the XML files.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=./dammloam-pki
days=3650
while getopts o:d: opt; do
  case $opt in
    o) out=$OPTARG ;;
    d) days=$OPTARG ;;
    *) echo "usage: $0 [-o OUT_DIR] [-d DAYS] [NAME...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -gt 0 ] || set -- dammloamd dammloam-operator dammloam-driver dammloam-consumer
command -v openssl >/dev/null || { echo "openssl not found" >&2; exit 1; }
mkdir -p "$out"
umask 077

# ECDSA P-256 keys: the builtin authentication plugin takes RSA-2048 or EC prime256v1.
new_key() { [ -f "$1" ] || openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$1"; }

ca() {  # ca NAME SUBJECT: self-signed CA certificate
  new_key "$out/$1_key.pem"
  [ -f "$out/$1.pem" ] || openssl req -new -x509 -sha256 -days "$days" -key "$out/$1_key.pem" \
      -subj "$2" -addext basicConstraints=critical,CA:TRUE -addext keyUsage=critical,keyCertSign,cRLSign,digitalSignature \
      -out "$out/$1.pem"
}
ca identity_ca "/O=dammloam/CN=dammloam identity CA"
ca permissions_ca "/O=dammloam/CN=dammloam permissions CA"

for name in "$@"; do
  mkdir -p "$out/$name"
  new_key "$out/$name/key.pem"
  if [ ! -f "$out/$name/cert.pem" ]; then
    openssl req -new -sha256 -key "$out/$name/key.pem" -subj "/O=dammloam/CN=$name" -out "$out/$name/csr.pem"
    openssl x509 -req -sha256 -days "$days" -in "$out/$name/csr.pem" -CA "$out/identity_ca.pem" \
      -CAkey "$out/identity_ca_key.pem" -CAcreateserial -out "$out/$name/cert.pem"
    rm -f "$out/$name/csr.pem"
  fi
done

# Governance and permissions: S/MIME, clear-signed (-text keeps the XML readable in the file).
for doc in governance permissions; do
  src=${DAMMLOAM_SECURITY_XML_DIR:-$here}/$doc.xml
  openssl smime -sign -text -in "$src" -out "$out/$doc.p7s" \
    -signer "$out/permissions_ca.pem" -inkey "$out/permissions_ca_key.pem"
done
chmod 0644 "$out"/*.pem "$out"/*.p7s "$out"/*/cert.pem
chmod 0600 "$out"/*_key.pem "$out"/*/key.pem
echo "PKI in $out: identities $*"
