// A small blocking HTTP/1.1 static file server over POSIX sockets, for `photoscene view OUT`:
// GET and HEAD only (405 otherwise), one response per connection (Connection: close), paths
// resolved under the root folder only (any ".." segment, or a path leaving the root through a
// symlink, is refused with 403), content types for the files a twin folder holds.
//
//   ps::StaticFileServer server("OUT", 0);          // binds 127.0.0.1 on a free port
//   std::cout << server.url("report.html") << "\n";  // http://127.0.0.1:PORT/report.html
//   server.serve();                                  // until the process is interrupted
#pragma once

#include <atomic>
#include <filesystem>
#include <string>

namespace ps {

class StaticFileServer {
 public:
  /// Binds `host`:`port` (port 0: a free port chosen by the system) and listens. Throws
  /// ps::InputError when `root` is not a folder or the given port is taken,
  /// std::runtime_error when no socket can be had at all.
  StaticFileServer(const std::filesystem::path& root, int port = 0,
                   const std::string& host = "127.0.0.1");
  ~StaticFileServer();
  StaticFileServer(const StaticFileServer&) = delete;
  StaticFileServer& operator=(const StaticFileServer&) = delete;

  int port() const { return port_; }
  /// "http://HOST:PORT/<path>"
  std::string url(const std::string& path = "") const;
  /// Serves requests (each connection on its own thread) until `stop` becomes true (checked
  /// every 100 ms) or forever when `stop` is null.
  void serve(const std::atomic<bool>* stop = nullptr);

 private:
  void handle(int client) const;
  std::filesystem::path root_;
  std::string host_;
  int port_ = 0;
  int listenFd_ = -1;
};

/// The Content-Type of a file by extension (.html, .js, .mjs, .css, .json, .gltf, .bin, .png,
/// .jpg, .svg, .exr, .hdr, .txt; application/octet-stream otherwise).
std::string contentTypeFor(const std::filesystem::path& file);

}  // namespace ps
