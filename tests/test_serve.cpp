// glint serve's internals that the browser tests reach poorly: who may talk
// to the server (Host, Origin), the request size cap, the name "Save as new"
// chooses, bad edits that must change nothing, tabs that go away in the
// middle of a stream, and an idle server that sleeps. A server runs in this
// process on a free port; requests are written by hand over a socket so
// every header is the test's. Every wait is for an event of the server
// (Server::wait_until) or the socket, never a sleep.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "glint/glint.h"
#include "glint/serve/rules.h"
#include "glint/serve/serve.h"
#include "glint/serve/session.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using glint::serve::Server;
using glint::serve::ServerStats;
using namespace std::chrono_literals;

// --- the rules, as functions -------------------------------------------------

// Undo keeps the newest steps that fit its byte budget: each step holds its
// own copy of the meshes.
TEST(ServeUndo, StepsAreBoundByTheirMeshBytes) {
  const fs::path dir = fs::temp_directory_path() / ("glint-serve-undo-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "tri.obj") << "v -1 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
  const std::string scene_text = R"({"camera":{"position":[0,0,4],"look_at":[0,0,0]},
    "materials":{"m":{"diffuse":[0.5,0.5,0.5],"shininess":1}},
    "objects":[{"type":"mesh","file":"tri.obj","material":"m"}]})";
  glint::api::Scene scene = glint::api::Scene::from_json(scene_text, dir, "undo.json");
  const size_t bytes = glint::serve::scene_bytes(scene);
  // 4 positions, 6 indices, 6 corner normals, 2 triangle materials.
  EXPECT_EQ(bytes, 4 * 12 + 6 * 4 + 6 * 12 + 2 * 4);
  std::vector<glint::api::Scene> steps;
  for (int k = 1; k <= 5; ++k) {
    scene.set("materials.m.shininess", k);
    steps.push_back(scene);
  }
  auto shininess = [](const glint::api::Scene& s) {
    return Json::parse(s.to_json())["materials"]["m"]["shininess"].get<int>();
  };
  std::vector<glint::api::Scene> a = steps;
  glint::serve::trim_undo(a, 200, bytes * 5 / 2);  // two steps fit
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(shininess(a[0]), 4);
  EXPECT_EQ(shininess(a[1]), 5);
  std::vector<glint::api::Scene> b = steps;
  glint::serve::trim_undo(b, 3, bytes * 100);  // the step limit
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(shininess(b[0]), 3);
  std::vector<glint::api::Scene> c = steps;
  glint::serve::trim_undo(c, 200, 0);  // the newest stays, whatever its size
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(shininess(c[0]), 5);
  fs::remove_all(dir);
}

TEST(ServeRules, IpLiterals) {
  for (const char* yes : {"127.0.0.1", "10.1.2.3", "[::1]", "[::ffff:127.0.0.1]", "[fe80::1]"})
    EXPECT_TRUE(glint::serve::is_ip_literal(yes)) << yes;
  for (const char* no : {"", "localhost", "evil.example", "999.0.0.1", "127.1", "127.0.0.1.nip.io", "[]",
                         "[evil.example]", "::1", "[::1", "0x7f000001"})
    EXPECT_FALSE(glint::serve::is_ip_literal(no)) << no;
}

TEST(ServeRules, HostHeaderNamesThisServerOnly) {
  using glint::serve::host_allowed;
  for (const char* yes : {"127.0.0.1:8123", "localhost:8123", "[::1]:8123", "192.168.1.20:8123"})
    EXPECT_TRUE(host_allowed(yes, "127.0.0.1", 8123)) << yes;
  // DNS rebinding: a name that resolves to us is not us. Nor is another
  // port, or no port, or a bracketed name.
  for (const char* no : {"evil.example:8123", "127.0.0.1.nip.io:8123", "localhost.evil.example:8123", "127.0.0.1:8124",
                         "127.0.0.1:80", "127.0.0.1", "localhost", "[::1]", "", ":8123", "[evil.example]:8123",
                         "127.0.0.1:8123:8123", "127.0.0.1:08123", "127.0.0.1:8123 "})
    EXPECT_FALSE(host_allowed(no, "127.0.0.1", 8123)) << no;
  // The --host name is ours too, and only that name.
  EXPECT_TRUE(host_allowed("preview.lan:8123", "preview.lan", 8123));
  EXPECT_FALSE(host_allowed("other.lan:8123", "preview.lan", 8123));
  EXPECT_TRUE(host_allowed("[::1]:8123", "::1", 8123));
}

TEST(ServeRules, OriginMustBeOurOwnPage) {
  using glint::serve::origin_allowed;
  EXPECT_TRUE(origin_allowed("http://127.0.0.1:8123", "127.0.0.1:8123"));
  EXPECT_TRUE(origin_allowed("http://[::1]:8123", "[::1]:8123"));
  for (const char* no :
       {"null", "", "http://127.0.0.1:8124", "https://127.0.0.1:8123", "http://evil.example", "http://127.0.0.1:8123/",
        "http://localhost:8123", "http://127.0.0.1:81234", "file://", "http://127.0.0.1:8123.evil.example"})
    EXPECT_FALSE(origin_allowed(no, "127.0.0.1:8123")) << no;
}

class ServeFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("glint-serve-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

TEST_F(ServeFiles, SaveAsNewNameIsBesideAndFree) {
  using glint::serve::new_file_beside;
  write(dir_ / "scene.json", "{}");
  EXPECT_EQ(new_file_beside(dir_ / "scene.json"), dir_ / "scene-edited.json");
  write(dir_ / "scene-edited.json", "{}");
  EXPECT_EQ(new_file_beside(dir_ / "scene.json"), dir_ / "scene-edited-2.json");
  write(dir_ / "scene-edited-2.json", "{}");
  EXPECT_EQ(new_file_beside(dir_ / "scene.json"), dir_ / "scene-edited-3.json");
  // A dangling link is a name taken: nothing is written through it.
  fs::create_symlink(dir_ / "nowhere.json", dir_ / "scene-edited-3.json");
  EXPECT_EQ(new_file_beside(dir_ / "scene.json"), dir_ / "scene-edited-4.json");
  // A model's scene is a JSON file beside the model; dots in the name stay in the stem.
  EXPECT_EQ(new_file_beside(dir_ / "model.obj"), dir_ / "model-edited.json");
  EXPECT_EQ(new_file_beside(dir_ / "a.b.json"), dir_ / "a.b-edited.json");
}

// --- a server in this process ---------------------------------------------------

struct Reply {
  int status = 0;  // 0: no status line (the connection closed first)
  std::string head, body;
};

int connect_to(int port, bool ipv6 = false) {
  const int fd = ::socket(ipv6 ? AF_INET6 : AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  int rc;
  if (ipv6) {
    sockaddr_in6 a{};
    a.sin6_family = AF_INET6;
    a.sin6_port = htons(static_cast<uint16_t>(port));
    a.sin6_addr = in6addr_loopback;
    rc = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  } else {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    rc = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  }
  if (rc != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool send_all(int fd, const std::string& data) {
  for (size_t at = 0; at < data.size();) {
    const ssize_t n = ::send(fd, data.data() + at, data.size() - at, MSG_NOSIGNAL);
    if (n <= 0) return false;
    at += static_cast<size_t>(n);
  }
  return true;
}

Reply parse_reply(const std::string& text) {
  Reply r;
  const size_t end = text.find("\r\n\r\n");
  r.head = text.substr(0, end);
  if (end != std::string::npos) r.body = text.substr(end + 4);
  if (text.rfind("HTTP/1.", 0) == 0 && text.size() >= 12) r.status = std::stoi(text.substr(9, 3));
  return r;
}

// One request, its whole answer: the server closes each connection after
// its answer, so the end of the answer is the end of the stream.
Reply round_trip(int port, const std::string& request, bool ipv6 = false) {
  const int fd = connect_to(port, ipv6);
  if (fd < 0) return {};
  send_all(fd, request);  // a refusal may come (and the socket close) before all is sent
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return parse_reply(text);
}

std::string http_request(const std::string& method, const std::string& target, const std::string& host,
                         const std::string& body = "", const std::string& extra_headers = "",
                         const std::string& content_type = "application/json") {
  std::string r = method + " " + target + " HTTP/1.1\r\n";
  if (!host.empty()) r += "Host: " + host + "\r\n";
  r += extra_headers;
  if (method == "POST")
    r += "Content-Type: " + content_type + "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  return r + "\r\n" + body;
}

// An open event stream (a tab), read as far as the test asks.
class EventStream {
 public:
  EventStream(int port, const std::string& host) : fd_(connect_to(port)) {
    send_all(fd_, http_request("GET", "/events", host));
  }
  ~EventStream() { close(); }
  // Reads until `text` has arrived; false if the stream ended first.
  bool read_until(const std::string& text) {
    char buffer[65536];
    while (received_.find(text, scanned_) == std::string::npos) {
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) return false;
      received_.append(buffer, static_cast<size_t>(n));
    }
    scanned_ = received_.find(text, scanned_) + text.size();
    return true;
  }
  int status() const { return parse_reply(received_).status; }
  const std::string& received() const { return received_; }
  // A tab closed (FIN), or a browser that died (reset: SO_LINGER 0).
  void close(bool reset = false) {
    if (fd_ < 0) return;
    if (reset) {
      const linger abort{1, 0};
      ::setsockopt(fd_, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
    }
    ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
  std::string received_;
  size_t scanned_ = 0;
};

constexpr auto kBound = 60s;  // a guard against a hang, never a pacing: every wait ends on an event

class ServeServer : public ServeFiles {
 protected:
  void SetUp() override {
    ServeFiles::SetUp();
    scene_ = dir_ / "scene.json";
    write(scene_, kScene);
  }
  void TearDown() override {
    server_.reset();
    ServeFiles::TearDown();
  }

  // The scene: small, so that frames come at once unless a test asks for more.
  static constexpr const char* kScene = R"({
  "render": { "width": 48, "height": 27, "samples_per_pixel": 1, "max_depth": 3 },
  "camera": { "position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 40 },
  "materials": {
    "red": { "diffuse": [0.8, 0.1, 0.1], "specular": 0.5, "shininess": 30 },
    "floor": { "diffuse": 0.6 }
  },
  "lights": [ { "type": "ambient", "ambient": 0.2 }, { "type": "point", "position": [2, 4, 3] } ],
  "objects": [
    { "type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": "red" },
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor" }
  ]
}
)";

  Server& start(const fs::path& scene, const std::string& host = "127.0.0.1") {
    glint::serve::ServeOptions options;
    options.scene_path = scene.string();
    options.host = host;
    options.port = 0;
    options.threads = 2;
    server_ = std::make_unique<Server>(options);
    server_->start();
    port_ = server_->port();
    host_ = (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port_);
    return *server_;
  }
  Reply get(const std::string& target, const std::string& extra = "") {
    return round_trip(port_, http_request("GET", target, host_, "", extra));
  }
  Reply post(const std::string& target, const std::string& body, const std::string& extra = "") {
    return round_trip(port_, http_request("POST", target, host_, body, extra));
  }
  Json state() {
    const Reply r = get("/api/state");
    EXPECT_EQ(r.status, 200);
    return Json::parse(r.body);
  }
  // The parts of the state an edit would change.
  static Json essence(const Json& s) {
    return {{"scene", s["scene"]},       {"scene_version", s["scene_version"]}, {"dirty", s["dirty"]},
            {"can_undo", s["can_undo"]}, {"can_redo", s["can_redo"]},           {"view", s["view"]}};
  }
  bool wait(const std::function<bool(const ServerStats&)>& condition) { return server_->wait_until(condition, kBound); }
  // The newest scene is on screen (a tab must be open for it to render).
  bool settled() {
    return wait([](const ServerStats& s) { return !s.rendering && s.full_frame_scene_version == s.scene_version; });
  }

  std::unique_ptr<Server> server_;
  fs::path scene_;
  int port_ = 0;
  std::string host_;
};

TEST_F(ServeServer, RefusesForeignHostsAndOrigins) {
  start(scene_);
  const std::string port = std::to_string(port_);
  EXPECT_EQ(get("/api/state").status, 200);
  EXPECT_EQ(round_trip(port_, http_request("GET", "/", "localhost:" + port)).status, 200);
  EXPECT_EQ(round_trip(port_, http_request("GET", "/", "[::1]:" + port)).status, 200);  // an IPv6 literal
  for (const std::string& host :
       {"evil.example:" + port, "127.0.0.1.nip.io:" + port, "127.0.0.1:" + std::to_string(port_ + 1),
        std::string("127.0.0.1"), std::string(""), "[evil.example]:" + port})
    EXPECT_EQ(round_trip(port_, http_request("GET", "/api/state", host)).status, 403) << host;
  // HTTP/1.0 without a Host header.
  EXPECT_EQ(round_trip(port_, "GET /api/state HTTP/1.0\r\n\r\n").status, 403);
  // A page elsewhere may not drive it or make it save; our own page may.
  const Json before = state();
  const std::string edit = R"({"edits":[{"op":"set","path":"render.max_depth","value":1}]})";
  for (const std::string& origin :
       {std::string("http://evil.example"), std::string("null"), "http://127.0.0.1:" + std::to_string(port_ + 1),
        "https://" + host_, "http://localhost:" + port}) {
    EXPECT_EQ(post("/api/edit", edit, "Origin: " + origin + "\r\n").status, 403) << origin;
    EXPECT_EQ(post("/api/save", R"({"mode":"new"})", "Origin: " + origin + "\r\n").status, 403) << origin;
  }
  EXPECT_EQ(post("/api/edit", edit, "Sec-Fetch-Site: cross-site\r\n").status, 403);
  EXPECT_EQ(post("/api/edit", edit, "Sec-Fetch-Site: same-site\r\n").status, 403);
  // A form can post text, never JSON: refused.
  EXPECT_EQ(round_trip(port_, http_request("POST", "/api/edit", host_, edit, "", "text/plain")).status, 415);
  EXPECT_EQ(round_trip(port_, http_request("PUT", "/api/edit", host_)).status, 405);
  EXPECT_EQ(essence(state()), essence(before));
  EXPECT_EQ(fs::directory_iterator(dir_)->path().filename(), "scene.json");  // nothing saved
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
  // Our own origin, and our own page's fetch: accepted.
  EXPECT_EQ(post("/api/edit", edit, "Origin: http://" + host_ + "\r\nSec-Fetch-Site: same-origin\r\n").status, 200);
  EXPECT_EQ(state()["scene"]["render"]["max_depth"], 1);
}

TEST_F(ServeServer, RefusesForeignHostsOnIpv6) {
  try {
    start(scene_, "::1");
  } catch (const glint::Error& e) {
    GTEST_SKIP() << "no IPv6 loopback here: " << e.what();
  }
  EXPECT_EQ(server_->url(), "http://[::1]:" + std::to_string(port_) + "/");
  EXPECT_EQ(round_trip(port_, http_request("GET", "/api/state", host_), true).status, 200);
  EXPECT_EQ(round_trip(port_, http_request("GET", "/api/state", "[::1]:" + std::to_string(port_ + 1)), true).status,
            403);
  EXPECT_EQ(round_trip(port_, http_request("GET", "/api/state", "[::1]"), true).status, 403);
  EXPECT_EQ(round_trip(port_, http_request("GET", "/api/state", "ip6-localhost:" + std::to_string(port_)), true).status,
            403);
  const std::string edit = R"({"edits":[{"op":"set","path":"render.max_depth","value":1}]})";
  EXPECT_EQ(round_trip(port_,
                       http_request("POST", "/api/edit", host_, edit,
                                    "Origin: http://127.0.0.1:" + std::to_string(port_) + "\r\n"),
                       true)
                .status,
            403);
  EXPECT_EQ(round_trip(port_, http_request("POST", "/api/edit", host_, edit, "Origin: http://" + host_ + "\r\n"), true)
                .status,
            200);
}

TEST_F(ServeServer, CapsRequestSizes) {
  start(scene_);
  const Json before = state();
  // One byte over 1 MiB: refused unread (413), the state as it was.
  const std::string big =
      "{\"edits\":[{\"op\":\"set\",\"path\":\"render.max_depth\",\"value\":1}]," + std::string((1 << 20), ' ') + "}";
  EXPECT_EQ(post("/api/edit", big).status, 413);
  // At the cap it is read (and this one is a good edit).
  const std::string edit = R"({"edits":[{"op":"set","path":"render.max_depth","value":2}]})";
  EXPECT_EQ(post("/api/edit", edit + std::string((1 << 20) - edit.size(), ' ')).status, 200);
  EXPECT_EQ(state()["scene"]["render"]["max_depth"], 2);
  // Chunked, past the cap: refused too (or the connection closed on it).
  std::string chunked = "POST /api/edit HTTP/1.1\r\nHost: " + host_ +
                        "\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
  const std::string chunk(64 * 1024, ' ');
  char size[16];
  std::snprintf(size, sizeof size, "%zx\r\n", chunk.size());
  for (int i = 0; i < 17; ++i) chunked += size + chunk + "\r\n";
  chunked += "0\r\n\r\n";
  const int status = round_trip(port_, chunked).status;
  EXPECT_TRUE(status == 413 || status == 400 || status == 0) << status;
  // Headers past httplib's limit (8 KiB a line): refused, never served.
  const int long_header =
      round_trip(port_, http_request("GET", "/api/state", host_, "", "X-Long: " + std::string(20000, 'x') + "\r\n"))
          .status;
  EXPECT_NE(long_header, 200);
  // A URI past its limit.
  EXPECT_NE(get("/frame/1.png?" + std::string(20000, 'x')).status, 200);
  Json after = state();
  EXPECT_EQ(after["scene"]["render"]["max_depth"], 2);
  after["scene"]["render"]["max_depth"] = before["scene"]["render"]["max_depth"];
  EXPECT_EQ(after["scene"], before["scene"]);
}

TEST_F(ServeServer, SaveAsNewNeverWritesWhereTheRequestSays) {
  start(scene_);
  ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"materials.red.shininess","value":7}]})").status, 200);
  const std::string outside =
      (dir_.parent_path() / ("glint-serve-evil-" + std::to_string(::getpid()) + ".json")).string();
  const Json asks = {{"mode", "new"},         {"path", outside},   {"name", "../evil.json"},
                     {"file", "/tmp/x.json"}, {"target", outside}, {"filename", "evil.json"}};
  Reply r = post("/api/save", asks.dump());
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Json::parse(r.body)["notice"], "saved as scene-edited.json");
  r = post("/api/save", asks.dump());
  EXPECT_EQ(Json::parse(r.body)["notice"], "saved as scene-edited-2.json");
  EXPECT_EQ(listing(), (std::vector<std::string>{"scene-edited-2.json", "scene-edited.json", "scene.json"}));
  EXPECT_FALSE(fs::exists(outside));
  // What was saved is the scene on screen, and loads as it.
  const Json shown = state()["scene"];
  EXPECT_EQ(Json::parse(glint::api::Scene::load(dir_ / "scene-edited.json").to_json()), shown);
  EXPECT_EQ(shown["materials"]["red"]["shininess"], 7);
  // The original is untouched until an overwrite, which a request cannot redirect either.
  EXPECT_EQ(Json::parse(std::ifstream(scene_))["materials"]["red"]["shininess"], 30);
  r = post("/api/save", Json{{"mode", "overwrite"}, {"path", outside}}.dump());
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(Json::parse(std::ifstream(scene_))["materials"]["red"]["shininess"], 7);
  EXPECT_FALSE(fs::exists(outside));
  EXPECT_EQ(post("/api/save", R"({"mode":"somewhere"})").status, 400);
  EXPECT_EQ(listing().size(), 3u);
}

TEST_F(ServeServer, SavingOverTheFileRendersNothingAgain) {
  Server& server = start(scene_);
  EventStream tab(port_, host_);  // a tab open: changes are rendered
  ASSERT_TRUE(tab.read_until("event: frame"));
  ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"materials.red.shininess","value":7}]})").status, 200);
  ASSERT_TRUE(settled());
  const ServerStats before = server.stats();
  ASSERT_EQ(post("/api/save", R"({"mode":"overwrite"})").status, 200);
  // The watcher reads the saved file: it holds what is on screen.
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.reloads > before.reloads; }));
  const ServerStats after = server.stats();
  EXPECT_EQ(after.scene_version, before.scene_version);
  EXPECT_EQ(after.renders, before.renders);
  EXPECT_EQ(state()["dirty"], false);
  // A change of the file that does change the scene is rendered.
  Json doc = Json::parse(std::ifstream(scene_));
  doc["materials"]["red"]["shininess"] = 9;
  write(scene_, doc.dump(2));
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.scene_version > after.scene_version; }));
  ASSERT_TRUE(settled());
  EXPECT_GT(server.stats().renders, after.renders);
  EXPECT_EQ(state()["scene"]["materials"]["red"]["shininess"], 9);
}

TEST_F(ServeServer, AModelIsSavedAsANewSceneOnly) {
  const fs::path model = dir_ / "model.obj";
  write(model, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const auto bytes = fs::file_size(model);
  start(model);
  EXPECT_EQ(state()["can_overwrite"], false);
  const Reply refused = post("/api/save", R"({"mode":"overwrite"})");
  EXPECT_EQ(refused.status, 400);
  EXPECT_NE(Json::parse(refused.body)["error"].get<std::string>().find("save as new"), std::string::npos);
  EXPECT_EQ(fs::file_size(model), bytes);
  ASSERT_EQ(post("/api/save", R"({"mode":"new"})").status, 200);
  // The framing rig, as a scene beside the model that names it.
  const glint::api::Scene saved = glint::api::Scene::load(dir_ / "model-edited.json");
  EXPECT_EQ(Json::parse(saved.to_json()), Json::parse(glint::api::Scene::load(model).to_json()));
  EXPECT_EQ(Json::parse(saved.to_json())["objects"][0]["file"], "model.obj");
}

TEST_F(ServeServer, BadRequestsChangeNothing) {
  start(scene_);
  const Json before = state();
  const std::string file_before = [&] {
    std::stringstream s;
    s << std::ifstream(scene_).rdbuf();
    return s.str();
  }();
  struct Bad {
    std::string target, body, message;  // `message`: part of the error the answer gives
  };
  const std::vector<Bad> bad = {
      {"/api/edit", R"({"edits":[{"op":"set","path":"materials.red.shininess","value":-3}]})",
       "materials.red.shininess: must be > 0"},
      // All or none: the good first edit is not applied either.
      {"/api/edit",
       R"({"edits":[{"op":"set","path":"render.max_depth","value":2},{"op":"set","path":"materials.red.ior","value":"glass"}]})",
       "materials.red.ior"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"render.width","value":1e300}]})", "render.width"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"materials.red.diffuse","value":[1,2]}]})",
       "materials.red.diffuse"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"lights[0].type","value":"laser"}]})", "lights[0].type"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"objects[0].file","value":"/etc/passwd"}]})", "objects[0]"},
      {"/api/edit", R"({"edits":[{"op":"erase","path":"materials.red"}]})", "red"},
      {"/api/edit", R"({"edits":[{"op":"erase","path":"objects[9]"}]})", "objects[9]"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"a..b","value":1}]})", "bad path"},
      {"/api/edit", R"({"edits":[{"op":"set","path":"camera.fov_y"}]})", "no value"},
      {"/api/edit", R"({"edits":[{"op":"rename","path":"camera"}]})", "unknown edit"},
      {"/api/edit", R"({"edits":[{"op":5,"path":"camera"}]})", "edits[0].op"},
      {"/api/edit", R"({"edits":[{"op":"set","path":7,"value":1}]})", "edits[0].path"},
      {"/api/edit", R"({"edits":[1]})", "edits[0]"},
      {"/api/edit", R"({"edits":[]})", "edits"},
      {"/api/edit", R"({"edits":{}})", "edits"},
      {"/api/edit", R"({})", "edits"},
      {"/api/edit", R"([])", "JSON object"},
      {"/api/edit", "{\"edits\": [", "JSON object"},
      {"/api/view", R"({"exposure":"bright"})", "exposure"},
      {"/api/view", R"({"exposure":1000})", "exposure"},
      {"/api/view", R"({"tonemap":"filmic"})", "tonemap"},
      {"/api/view", R"({"pass":"../../etc/passwd"})", "unknown pass"},
      {"/api/undo", R"({})", "nothing to undo"},
      {"/api/undo", R"({"redo":true})", "nothing to redo"},
      {"/api/resolve", R"({"keep":"file"})", "no conflict"},
      {"/api/explain", R"({"x":-1,"y":0})", ""},
      {"/api/explain", R"({"x":"a","y":0})", "explain"},
      {"/api/explain", R"({"x":1e12,"y":0})", "explain"},
      {"/api/save", R"({"mode":7})", "mode"},
  };
  for (const Bad& b : bad) {
    const Reply r = post(b.target, b.body);
    EXPECT_EQ(r.status, 400) << b.target << " " << b.body;
    const Json answer = Json::parse(r.body, nullptr, false);
    ASSERT_TRUE(answer.is_object() && answer.contains("error")) << r.body;
    EXPECT_NE(answer["error"].get<std::string>().find(b.message), std::string::npos)
        << answer["error"] << " for " << b.body;
    EXPECT_EQ(essence(state()), essence(before)) << b.body;
  }
  std::stringstream file_after;
  file_after << std::ifstream(scene_).rdbuf();
  EXPECT_EQ(file_after.str(), file_before);
  // And the server goes on: a good edit is taken.
  EXPECT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"materials.red.shininess","value":12}]})").status, 200);
  EXPECT_EQ(state()["scene"]["materials"]["red"]["shininess"], 12);
}

TEST_F(ServeServer, ATabThatGoesAwayMidStreamCostsNothing) {
  Server& server = start(scene_);
  for (const bool reset : {false, true}) {
    SCOPED_TRACE(reset ? "the connection reset" : "the connection closed");
    auto tab = std::make_unique<EventStream>(port_, host_);
    ASSERT_TRUE(tab->read_until("event: frame"));  // of the scene as it is
    ASSERT_TRUE(wait([](const ServerStats& s) { return s.tabs == 1 && !s.rendering; }));
    const uint64_t renders_before = server.stats().renders;
    // A full frame that takes long (400 x 225 at 256 samples): the tab goes
    // away while it renders.
    ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"render.width","value":400},
      {"op":"set","path":"render.height","value":225},{"op":"set","path":"render.samples_per_pixel","value":256}]})")
                  .status,
              200);
    const uint64_t version = server.stats().scene_version;
    ASSERT_TRUE(wait([&](const ServerStats& s) { return s.rendering && s.renders > renders_before; }));
    const uint64_t full_frames = server.stats().full_frames;
    tab->close(reset);
    // Let go of at once (no write needed to notice), and the render for
    // nobody cancelled within a row.
    ASSERT_TRUE(wait([](const ServerStats& s) { return s.tabs == 0 && !s.rendering; }));
    EXPECT_EQ(server.stats().full_frames, full_frames);
    EXPECT_EQ(server.stats().scene_version, version);
    // Nobody watching: edits are taken, nothing is rendered.
    const uint64_t renders = server.stats().renders;
    ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"render.width","value":48},
      {"op":"set","path":"render.height","value":27},{"op":"set","path":"render.samples_per_pixel","value":1}]})")
                  .status,
              200);
    EXPECT_EQ(server.stats().renders, renders);
    // A tab again: the newest scene is rendered for it.
    EventStream again(port_, host_);
    ASSERT_TRUE(again.read_until("event: frame"));
    ASSERT_TRUE(wait([&](const ServerStats& s) { return s.full_frames > full_frames && !s.rendering; }));
    again.close();
    ASSERT_TRUE(wait([](const ServerStats& s) { return s.tabs == 0; }));
  }
}

TEST_F(ServeServer, TabsBeyondTheLimitAreRefusedUntilOneCloses) {
  Server& server = start(scene_);
  std::vector<std::unique_ptr<EventStream>> tabs;
  for (int i = 0; i < 12; ++i) {
    tabs.push_back(std::make_unique<EventStream>(port_, host_));
    ASSERT_TRUE(tabs.back()->read_until("event: state"));
  }
  EXPECT_EQ(server.stats().tabs, 12);
  EventStream refused(port_, host_);
  EXPECT_FALSE(refused.read_until("event: state"));
  EXPECT_EQ(refused.status(), 503);
  // Closed tabs free their places at once.
  tabs[3]->close();
  tabs[7]->close(true);
  ASSERT_TRUE(wait([](const ServerStats& s) { return s.tabs == 10; }));
  EventStream accepted(port_, host_);
  EXPECT_TRUE(accepted.read_until("event: state"));
  // The server still answers while its streams are open.
  EXPECT_EQ(get("/api/state").status, 200);
}

// The width and height a PNG says it has (its IHDR chunk).
std::pair<int, int> png_size(const std::string& png) {
  if (png.size() < 24 || png.compare(1, 3, "PNG") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return static_cast<int>((static_cast<unsigned char>(png[at]) << 24) |
                            (static_cast<unsigned char>(png[at + 1]) << 16) |
                            (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]));
  };
  return {be32(16), be32(20)};
}

std::string png_of(const glint::api::Scene& scene, const glint::api::RenderOptions& options = {}) {
  const glint::api::Renderer renderer(scene);
  const auto bytes = glint::api::encode_image(renderer.render(options).image, "png");
  return std::string(bytes.begin(), bytes.end());
}

TEST_F(ServeServer, ACoarseFrameFirstThenTheFullOne) {
  Json doc = Json::parse(kScene);
  doc["render"]["width"] = 480;
  doc["render"]["height"] = 270;
  doc["render"]["samples_per_pixel"] = 4;
  write(scene_, doc.dump(2));
  Server& server = start(scene_);
  EventStream tab(port_, host_);
  ASSERT_TRUE(wait([](const ServerStats& s) { return s.full_frames == 1 && !s.rendering; }));
  EXPECT_EQ(server.stats().frames, 2u);
  // Frame 1: about 40,000 pixels at 1 sample (the scale s = sqrt(480 * 270 / 40000) = 1.8).
  const double s = std::sqrt(480.0 * 270.0 / 40000.0);
  const int w = static_cast<int>(std::lround(480 / s)), h = static_cast<int>(std::lround(270 / s));
  ASSERT_EQ(w, 267);
  const glint::api::Scene scene = glint::api::Scene::load(scene_);
  const Reply coarse = get("/frame/1.png");
  ASSERT_EQ(coarse.status, 200);
  EXPECT_EQ(png_size(coarse.body), std::make_pair(w, h));
  glint::api::RenderOptions small;
  small.width = w;
  small.height = h;
  small.samples_per_pixel = 1;
  EXPECT_EQ(coarse.body, png_of(scene, small));
  // Frame 2: the scene's size and samples, as glint render writes it.
  const Reply full = get("/frame/2.png");
  EXPECT_EQ(png_size(full.body), std::make_pair(480, 270));
  EXPECT_EQ(full.body, png_of(scene));
  // And its exact values.
  const Reply pfm = get("/frame/2.pfm");
  const glint::api::Renderer renderer(scene);
  const auto expected = glint::api::encode_image(renderer.render({}).image, "pfm");
  EXPECT_EQ(pfm.body, std::string(expected.begin(), expected.end()));
  EXPECT_EQ(get("/frame/1.pfm").status, 404);  // a coarse frame has no exact values to give
}

TEST_F(ServeServer, ANewerEditCancelsTheRenderInFlight) {
  Server& server = start(scene_);
  EventStream tab(port_, host_);
  ASSERT_TRUE(wait([](const ServerStats& s) { return s.full_frames == 1 && !s.rendering; }));
  const uint64_t renders = server.stats().renders, full_frames = server.stats().full_frames;
  // A frame that takes long (400 x 225 at 256 samples)...
  ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"render.width","value":400},
    {"op":"set","path":"render.height","value":225},{"op":"set","path":"render.samples_per_pixel","value":256}]})")
                .status,
            200);
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.rendering && s.renders > renders; }));
  // ...and, while it renders, the next edit: that frame is never finished.
  ASSERT_EQ(post("/api/edit", R"({"edits":[{"op":"set","path":"render.samples_per_pixel","value":1},
    {"op":"set","path":"render.width","value":40}]})")
                .status,
            200);
  const uint64_t version = server.stats().scene_version;
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.full_frames > full_frames && !s.rendering; }));
  EXPECT_EQ(server.stats().full_frames, full_frames + 1);
  EXPECT_EQ(server.stats().scene_version, version);
  EXPECT_EQ(png_size(get("/frame/" + std::to_string(server.stats().frames) + ".png").body), std::make_pair(40, 225));
}

// --- an idle server sleeps ---------------------------------------------------------

// Whether a thread is blocked in a system call that has no timeout (so it
// runs again only when something happens), from /proc/self/task/TID/syscall:
// the call's number and its arguments (x86-64 numbering).
bool blocked_for_good(const std::string& syscall_line) {
  std::istringstream in(syscall_line);
  long number = -1;
  in >> number;
  std::vector<unsigned long long> args;
  std::string word;
  while (in >> word && args.size() < 6) args.push_back(std::stoull(word, nullptr, 16));
  if (args.size() < 6) return false;  // "running", or not in a system call
  const auto infinite_ms = [](unsigned long long v) { return static_cast<int>(v & 0xffffffffu) < 0; };
  switch (number) {
    case SYS_futex: return args[3] == 0;         // no timeout
    case SYS_poll: return infinite_ms(args[2]);  // timeout -1
    case SYS_ppoll: return args[2] == 0;
    case SYS_epoll_wait:
    case SYS_epoll_pwait: return infinite_ms(args[3]);
    case SYS_select:
    case SYS_pselect6: return args[4] == 0;
    case SYS_accept:
    case SYS_accept4:
    case SYS_read:
    case SYS_recvfrom: return true;
    case SYS_rt_sigtimedwait: return args[2] == 0;
    default: return false;
  }
}

// The threads of this process other than the caller that are not blocked for good.
std::vector<std::string> threads_awake() {
  std::vector<std::string> awake;
  const std::string self = std::to_string(::syscall(SYS_gettid));
  for (const auto& task : fs::directory_iterator("/proc/self/task")) {
    if (task.path().filename() == self) continue;
    std::string line, name;
    std::getline(std::ifstream(task.path() / "syscall"), line);
    std::getline(std::ifstream(task.path() / "comm"), name);
    if (!blocked_for_good(line)) awake.push_back(task.path().filename().string() + " " + name + ": " + line);
  }
  return awake;
}

TEST_F(ServeServer, IdleServerThreadsAllSleepWithoutTimeouts) {
#if !defined(__x86_64__)
  GTEST_SKIP() << "the system call numbers here are x86-64's";
#endif
  Server& server = start(scene_);
  EventStream tab(port_, host_);
  ASSERT_TRUE(tab.read_until("event: frame"));
  ASSERT_TRUE(wait([](const ServerStats& s) { return s.full_frames >= 1 && !s.rendering && s.tabs == 1; }));
  // A tab is open and nothing changes. The threads that served the last
  // requests get back to their queue a moment after the answers went out:
  // checked again (no sleep) until then.
  std::vector<std::string> awake = threads_awake();
  for (const auto deadline = std::chrono::steady_clock::now() + 10s;
       !awake.empty() && std::chrono::steady_clock::now() < deadline; awake = threads_awake())
    std::this_thread::yield();
  EXPECT_TRUE(awake.empty()) << ::testing::PrintToString(awake);
  // With no tab at all, the same.
  tab.close();
  ASSERT_TRUE(wait([](const ServerStats& s) { return s.tabs == 0; }));
  awake = threads_awake();
  for (const auto deadline = std::chrono::steady_clock::now() + 10s;
       !awake.empty() && std::chrono::steady_clock::now() < deadline; awake = threads_awake())
    std::this_thread::yield();
  EXPECT_TRUE(awake.empty()) << ::testing::PrintToString(awake);
  EXPECT_EQ(server.stats().tabs, 0);
}

// --- files: read once, watched ---------------------------------------------------

TEST_F(ServeServer, EditsReadNoFileAndTheWatcherReadsAChangedOne) {
  write(dir_ / "tri.obj", "mtllib tri.mtl\nv -1 0 0\nv 1 0 0\nv 0 1.5 0\nusemtl paint\nf 1 2 3\n");
  write(dir_ / "tri.mtl", "newmtl paint\nKd 0.2 0.7 0.3\n");
  Json doc = Json::parse(kScene);
  doc["objects"].push_back({{"type", "mesh"}, {"file", "tri.obj"}});
  write(scene_, doc.dump(2));
  Server& server = start(scene_);
  EventStream tab(port_, host_);
  ASSERT_TRUE(tab.read_until("event: frame"));
  EXPECT_EQ(server.stats().file_reads, 1u);
  // Materials, lights, camera, settings: no file is read again.
  for (
      const char* edit :
      {R"({"op":"set","path":"materials.red.shininess","value":5})",
       R"({"op":"set","path":"lights[1].position","value":[1,5,2]})",
       R"({"op":"set","path":"camera.fov_y","value":35})", R"({"op":"set","path":"render.max_depth","value":2})",
       R"({"op":"append","path":"objects","value":{"type":"mesh","file":"tri.obj","transform":{"translate":[1,0,0]}}})"})
    ASSERT_EQ(post("/api/edit", std::string("{\"edits\":[") + edit + "]}").status, 200) << edit;
  ASSERT_TRUE(settled());
  EXPECT_EQ(server.stats().file_reads, 1u);
  // The acceleration structure: built for the first frame and for the
  // object added, kept for the rest.
  EXPECT_EQ(server.stats().builds, 2);
  EXPECT_EQ(Json::parse(get("/api/state").body)["stats"]["file_reads"], 1);
  // The .mtl changes on disk: the watcher reloads, and the mesh (read with it) is read again.
  const uint64_t version = server.stats().scene_version;
  write(dir_ / "tri.mtl", "newmtl paint\nKd 0.9 0.1 0.1\n");
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.scene_version > version; }));
  EXPECT_EQ(server.stats().file_reads, 2u);
  // Only a file the scene names changed, not the scene file: the unsaved
  // edits stay (no conflict to resolve), over the new .mtl.
  const Json after = state();
  EXPECT_EQ(after["conflict"], false);
  EXPECT_EQ(after["dirty"], true);
  EXPECT_EQ(after["scene"]["materials"]["red"]["shininess"], 5);
  // New materials, the same triangles: no new acceleration structure.
  ASSERT_TRUE(settled());
  EXPECT_EQ(server.stats().builds, 2);
  // The mesh by rename, as editors save.
  const uint64_t version2 = server.stats().scene_version;
  write(dir_ / ".tri.obj.tmp", "mtllib tri.mtl\nv -1 0 0\nv 1 0 0\nv 0 0.5 0\nusemtl paint\nf 1 2 3\n");
  fs::rename(dir_ / ".tri.obj.tmp", dir_ / "tri.obj");
  ASSERT_TRUE(wait([&](const ServerStats& s) { return s.scene_version > version2; }));
  EXPECT_EQ(server.stats().file_reads, 3u);
  ASSERT_TRUE(settled());
  EXPECT_EQ(server.stats().builds, 3);
  // Without the meshes and back (undo): the file's own scene names the mesh,
  // so it stayed in the cache.
  ASSERT_EQ(
      post("/api/edit", R"({"edits":[{"op":"erase","path":"objects[3]"},{"op":"erase","path":"objects[2]"}]})").status,
      200);
  ASSERT_EQ(post("/api/undo", "{}").status, 200);
  EXPECT_EQ(server.stats().file_reads, 3u);
}

}  // namespace
