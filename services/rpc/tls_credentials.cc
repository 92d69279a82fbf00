#include "services/rpc/tls_credentials.h"

#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "core/status_macros.h"

namespace fitbase::rpc {
namespace {

absl::StatusOr<std::string> ReadPem(const std::filesystem::path& path, const char* what) {
  if (path.empty()) return std::string();
  absl::StatusOr<std::string> pem = core::ReadFileToString(path);
  if (!pem.ok()) {
    return absl::NotFoundError(absl::StrCat("TLS ", what, " ", path.string(), ": ",
                                            pem.status().message()));
  }
  return pem;
}

}  // namespace

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> TlsServerCredentials(
    const TlsFiles& files) {
  if (files.cert.empty() || files.key.empty()) {
    return absl::InvalidArgumentError("a TLS server needs a certificate and its key");
  }
  grpc::SslServerCredentialsOptions options(
      files.ca.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                       : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  ASSIGN_OR_RETURN(options.pem_root_certs, ReadPem(files.ca, "CA"));
  grpc::SslServerCredentialsOptions::PemKeyCertPair pair;
  ASSIGN_OR_RETURN(pair.private_key, ReadPem(files.key, "key"));
  ASSIGN_OR_RETURN(pair.cert_chain, ReadPem(files.cert, "certificate"));
  options.pem_key_cert_pairs.push_back(std::move(pair));
  return grpc::SslServerCredentials(options);
}

absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> TlsChannelCredentials(
    const TlsFiles& files) {
  if (files.cert.empty() != files.key.empty()) {
    return absl::InvalidArgumentError("a TLS client certificate needs its key, and back");
  }
  grpc::SslCredentialsOptions options;
  ASSIGN_OR_RETURN(options.pem_root_certs, ReadPem(files.ca, "CA"));
  ASSIGN_OR_RETURN(options.pem_private_key, ReadPem(files.key, "key"));
  ASSIGN_OR_RETURN(options.pem_cert_chain, ReadPem(files.cert, "certificate"));
  return grpc::SslCredentials(options);
}

}  // namespace fitbase::rpc
