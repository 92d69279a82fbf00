#!/usr/bin/env bash
# Test-only certificates for the mutual-TLS tests (never for deployment): a CA, a server
# certificate for the name "fitbase-coordinator" (tests override the target name), and a
# worker's client certificate, signed by the CA, and an intruder's self-signed one; valid for
# 100 years. Rerun to replace them.
set -euo pipefail
cd "$(dirname "$0")"
days=36500
openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.pem -days $days \
  -subj "/CN=fitbase test CA" 2>/dev/null
for name in server worker; do
  cn=$([ "$name" = server ] && echo fitbase-coordinator || echo fitbase-worker)
  openssl req -newkey rsa:2048 -nodes -keyout "$name.key" -out "$name.csr" -subj "/CN=$cn" 2>/dev/null
  printf 'subjectAltName=DNS:%s\n' "$cn" > "$name.ext"
  openssl x509 -req -in "$name.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -out "$name.pem" \
    -days $days -extfile "$name.ext" 2>/dev/null
  rm "$name.csr" "$name.ext"
done
# A client certificate from no CA the server trusts.
openssl req -x509 -newkey rsa:2048 -nodes -keyout intruder.key -out intruder.pem -days $days \
  -subj "/CN=intruder" 2>/dev/null
rm -f ca.srl ca.key
