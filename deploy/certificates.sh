#!/bin/sh
# Certificates for a Dask cluster's TLS (exprclone serve --scheduler tls://..., docs/howto/deploy.rst): a certificate
# authority of the cluster's own, and a certificate it signs for each kind of member (the scheduler, the workers, the
# replicas), each with its private key. The scheduler and the workers refuse any client, and any worker, without a
# certificate of this authority: keep ca.key off the cluster's machines once the certificates are made.
#
#     sh deploy/certificates.sh DIR        # DIR (default: certificates) gets ca.pem, ca.key and NAME.pem, NAME.key
#
# Needs only the openssl command. Certificates last DAYS days (default 825): make new ones before then.
set -eu
dir=${1:-certificates}
days=${DAYS:-825}
mkdir -p "$dir"
cd "$dir"
umask 077  # the private keys readable by their owner alone
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days "$days" \
    -subj "/CN=exprclone cluster CA" -keyout ca.key -out ca.pem
for name in scheduler worker replica; do
    openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes \
        -subj "/CN=exprclone $name" -keyout "$name.key" -out "$name.csr"
    openssl x509 -req -in "$name.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -days "$days" -out "$name.pem"
    rm "$name.csr"
done
chmod 644 ca.pem scheduler.pem worker.pem replica.pem
echo "certificates in $dir: ca.pem, and scheduler, worker and replica (.pem and .key)"
