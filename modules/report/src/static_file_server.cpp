#include "photoscene/report/static_file_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include "photoscene/core/log.hpp"
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "photoscene/core/error.hpp"

namespace ps {

namespace fs = std::filesystem;

namespace {

bool sendAll(int fd, const char* data, size_t n) {
  while (n > 0) {
    const ssize_t w = ::send(fd, data, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    data += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}

void sendResponse(int fd, int code, const std::string& reason, const std::string& type,
                  const std::string& body, bool head, const std::string& extraHeaders = "") {
  std::ostringstream os;
  os << "HTTP/1.1 " << code << " " << reason << "\r\nContent-Type: " << type
     << "\r\nContent-Length: " << body.size()
     << "\r\nConnection: close\r\nCache-Control: no-cache\r\n"
     << extraHeaders << "\r\n";
  const std::string hdr = os.str();
  if (sendAll(fd, hdr.data(), hdr.size()) && !head) sendAll(fd, body.data(), body.size());
}

void sendError(int fd, int code, const std::string& reason, bool head,
               const std::string& extra = "") {
  sendResponse(fd, code, reason, "text/plain; charset=utf-8",
               std::to_string(code) + " " + reason + "\n", head, extra);
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// Percent-decodes a URL path; false on a malformed escape or a NUL byte.
bool percentDecode(const std::string& in, std::string* out) {
  out->clear();
  for (size_t i = 0; i < in.size(); ++i) {
    char c = in[i];
    if (c == '%') {
      if (i + 2 >= in.size()) return false;
      const int a = hexValue(in[i + 1]), b = hexValue(in[i + 2]);
      if (a < 0 || b < 0) return false;
      c = static_cast<char>(a * 16 + b);
      i += 2;
    }
    if (c == '\0') return false;
    *out += c;
  }
  return true;
}

}  // namespace

std::string contentTypeFor(const fs::path& file) {
  std::string e = file.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  static const std::map<std::string, std::string> types = {
      {".html", "text/html; charset=utf-8"},
      {".htm", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".gltf", "model/gltf+json"},
      {".glb", "model/gltf-binary"},
      {".bin", "application/octet-stream"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},
      {".svg", "image/svg+xml"},
      {".webp", "image/webp"},
      {".exr", "image/x-exr"},
      {".hdr", "image/vnd.radiance"},
      {".obj", "text/plain; charset=utf-8"},
      {".txt", "text/plain; charset=utf-8"},
  };
  auto it = types.find(e);
  return it == types.end() ? "application/octet-stream" : it->second;
}

StaticFileServer::StaticFileServer(const fs::path& root, int port, const std::string& host)
    : host_(host) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw InputError(root.string(), "", "a folder to serve");
  root_ = fs::canonical(root);
  listenFd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  PS_Check(listenFd_ >= 0, "socket(): " << std::strerror(errno));
  const int one = 1;
  ::setsockopt(listenFd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    ::close(listenFd_);
    throw InputError("--host", host, "an IPv4 address such as 127.0.0.1");
  }
  if (::bind(listenFd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
      ::listen(listenFd_, 64) != 0) {
    const std::string err = std::strerror(errno);
    ::close(listenFd_);
    listenFd_ = -1;
    if (port != 0)  // the port the user asked for is taken (or not allowed)
      throw InputError("--port", std::to_string(port), "a free port on " + host + ", got: " + err);
    throw std::runtime_error("cannot listen on " + host + ": " + err);
  }
  socklen_t len = sizeof(addr);
  ::getsockname(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
}

StaticFileServer::~StaticFileServer() {
  if (listenFd_ >= 0) ::close(listenFd_);
}

std::string StaticFileServer::url(const std::string& path) const {
  return "http://" + host_ + ":" + std::to_string(port_) + "/" + path;
}

void StaticFileServer::serve(const std::atomic<bool>* stop) {
  std::vector<std::thread> workers;
  while (!(stop && stop->load())) {
    pollfd p{listenFd_, POLLIN, 0};
    const int r = ::poll(&p, 1, 100);
    if (r < 0 && errno != EINTR) break;
    if (r <= 0) continue;
    const int client = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    workers.emplace_back([this, client] {
      handle(client);
      ::close(client);
    });
    // reap finished workers now and then (each lives for one request)
    if (workers.size() > 64) {
      for (auto& w : workers) w.join();
      workers.clear();
    }
  }
  for (auto& w : workers) w.join();
}

void StaticFileServer::handle(int client) const {
  // read the request head (up to 16 KiB, 5 s)
  std::string req;
  char buf[4096];
  while (req.find("\r\n\r\n") == std::string::npos && req.size() < 16384) {
    pollfd p{client, POLLIN, 0};
    if (::poll(&p, 1, 5000) <= 0) return;
    const ssize_t n = ::recv(client, buf, sizeof(buf), 0);
    if (n <= 0) return;
    req.append(buf, static_cast<size_t>(n));
  }
  std::istringstream line(req.substr(0, req.find("\r\n")));
  std::string method, target, version;
  line >> method >> target >> version;
  const bool head = method == "HEAD";
  if (method.empty() || target.empty() || version.rfind("HTTP/1.", 0) != 0) {
    sendError(client, 400, "Bad Request", false);
    return;
  }
  if (method != "GET" && !head) {
    sendError(client, 405, "Method Not Allowed", false, "Allow: GET, HEAD\r\n");
    return;
  }
  target = target.substr(0, target.find_first_of("?#"));
  std::string decoded;
  if (target.empty() || target[0] != '/' || !percentDecode(target, &decoded)) {
    sendError(client, 400, "Bad Request", head);
    return;
  }
  // refuse any ".." segment (and backslashes, which some clients treat as separators)
  fs::path rel;
  std::stringstream segs(decoded);
  std::string seg;
  while (std::getline(segs, seg, '/')) {
    if (seg.empty() || seg == ".") continue;
    if (seg == ".." || seg.find('\\') != std::string::npos) {
      sendError(client, 403, "Forbidden", head);
      return;
    }
    rel /= seg;
  }
  fs::path file = root_ / rel;
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    if (fs::exists(file / "index.html"))
      file /= "index.html";
    else if (fs::exists(file / "report.html"))
      file /= "report.html";
  }
  const fs::path canon = fs::weakly_canonical(file, ec);
  const std::string rootStr = root_.string() + "/";
  if (ec || (canon != root_ && canon.string().rfind(rootStr, 0) != 0)) {
    sendError(client, 403, "Forbidden", head);  // left the root (a symlink)
    return;
  }
  if (!fs::is_regular_file(canon, ec)) {
    sendError(client, 404, "Not Found", head);
    return;
  }
  std::ifstream in(canon, std::ios::binary);
  if (!in) {
    sendError(client, 403, "Forbidden", head);
    return;
  }
  const auto size = fs::file_size(canon, ec);
  std::ostringstream os;
  os << "HTTP/1.1 200 OK\r\nContent-Type: " << contentTypeFor(canon)
     << "\r\nContent-Length: " << size
     << "\r\nConnection: close\r\nCache-Control: no-cache\r\n\r\n";
  const std::string hdr = os.str();
  if (!sendAll(client, hdr.data(), hdr.size()) || head) return;
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const std::streamsize n = in.gcount();
    if (n <= 0 || !sendAll(client, chunk.data(), static_cast<size_t>(n))) break;
  }
  spdlog::debug("view: {} {} 200", method, target);
}

}  // namespace ps
