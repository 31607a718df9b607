// The HTTP server of `dynpm view`: GET and HEAD of a fixed set of paths on 127.0.0.1, one
// thread, poll(). Our own rather than cpp-httplib 0.11 (Debian 12), which stores every header
// line before a handler can look (200,000 lines: answered 200, +22 MB), keeps a reading thread
// per slow client (12 of them stalled every other request past 1 s), and binds with
// SO_REUSEPORT (two servers on one port shared its requests). docs/viewer.md "Security and
// limits".
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

// What a path answers: bytes held in memory, or a model file, opened anew for each request
// and sent from that open file with the size it had then.
struct ServedFile {
  std::string path;  // "/index.html"
  std::string content_type;
  std::string_view bytes;  // unused for a model
  bool is_model = false;
  std::string disk_path;  // a model's file on disk; empty: ServerOptions::model
};

struct ServerOptions {
  std::vector<ServedFile> files;
  std::string model;          // the .dpm on disk
  double throttle_bytes = 0;  // bytes per second for the model; 0: as fast as it goes
  std::string content_security_policy;
};

// Limits: a request head (line and headers) of at most kMaxHead bytes and kMaxHeaderLines
// lines, complete within kHeadSeconds of the connection becoming ready for it.
inline constexpr size_t kMaxHead = 16 * 1024;
inline constexpr size_t kMaxHeaderLines = 100;
inline constexpr int kHeadSeconds = 10;

struct Listener {
  int fd = -1;
  int port = 0;
};

// A listening socket on 127.0.0.1:port (0: a free port), with SO_REUSEADDR only, so that a
// second server on a taken port fails; the error names the address ("in use?").
Result<Listener> listen_on_loopback(int port);

// Serves on the listener until SIGINT or SIGTERM, which the caller has blocked; closes it.
Status serve(const ServerOptions& options, Listener listener);

}  // namespace dynpm::cli
