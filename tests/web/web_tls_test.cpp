// HTTPS: with a certificate (made here with `openssl req`, as docs/web.md says) the server speaks
// TLS only, the session cookie is Secure and HSTS is sent; a bad certificate is refused at start.
#include <cstdlib>
#include <fstream>

#include "trueaxis/core/input_error.hpp"
#include "web_fixture.hpp"

namespace trueaxis::web::testing {
namespace {

namespace fs = std::filesystem;

class TlsTest : public trueaxis::testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    const std::string cmd = "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 1 "
                            "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 -keyout " +
                            (dir_ / "key.pem").string() + " -out " + (dir_ / "cert.pem").string() + " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << "openssl could not make a test certificate";
    access_ = std::make_unique<AccessDb>((dir_ / "users.db").string());
    access_->AddUser("viewer", Role::kViewer, kViewerPassword, HashCost::kMinimum);
    shop_ = std::make_unique<SyntheticShop>(3);
  }
  void TearDown() override {
    access_.reset();
    TempDirTest::TearDown();
  }
  WebServerOptions Options() const {
    WebServerOptions o;
    o.port = 0;
    o.tls_cert_file = (dir_ / "cert.pem").string();
    o.tls_key_file = (dir_ / "key.pem").string();
    return o;
  }
  std::unique_ptr<AccessDb> access_;
  std::unique_ptr<SyntheticShop> shop_;
};

TEST_F(TlsTest, ServesHttpsWithSecureCookiesAndHsts) {
  WebServer server(*shop_, *access_, Options());
  server.Start();
  EXPECT_EQ(server.Url().rfind("https://", 0), 0u);
  httplib::SSLClient c("127.0.0.1", server.port());
  c.set_ca_cert_path((dir_ / "cert.pem").string().c_str());
  c.enable_server_certificate_verification(true);
  auto r = c.Post("/api/login", nlohmann::json{{"user", "viewer"}, {"password", kViewerPassword}}.dump(), "application/json");
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->get_header_value("Set-Cookie").find("; Secure"), std::string::npos);
  EXPECT_NE(r->get_header_value("Strict-Transport-Security").find("max-age="), std::string::npos);
  // Plain HTTP on the TLS port gets no page.
  httplib::Client plain("127.0.0.1", server.port());
  plain.set_read_timeout(3, 0);
  auto p = plain.Get("/login.html");
  EXPECT_TRUE(!p || p->status != 200);
}

TEST_F(TlsTest, RefusesAMissingOrMismatchedCertificate) {
  WebServerOptions o = Options();
  o.tls_key_file = "";
  EXPECT_THROW(WebServer(*shop_, *access_, o), InputError) << "a certificate without its key";
  o = Options();
  o.tls_cert_file = (dir_ / "missing.pem").string();
  EXPECT_THROW(WebServer(*shop_, *access_, o), InputError);
  std::ofstream((dir_ / "junk.pem").string()) << "-----BEGIN CERTIFICATE-----\nnot base64\n-----END CERTIFICATE-----\n";
  o = Options();
  o.tls_cert_file = (dir_ / "junk.pem").string();
  EXPECT_THROW(WebServer(*shop_, *access_, o), InputError);
}

}  // namespace
}  // namespace trueaxis::web::testing
