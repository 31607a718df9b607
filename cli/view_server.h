// The HTTP server of `dynpm view` and `dynpm serve`: GET and HEAD of a fixed set of paths on
// 127.0.0.1, one thread, poll(). Our own rather than cpp-httplib 0.11 (Debian 12), which stores
// every header line before a handler can look (200,000 lines: answered 200, +22 MB), keeps a
// reading thread per slow client (12 of them stalled every other request past 1 s), and binds with
// SO_REUSEPORT (two servers on one port shared its requests). docs/viewer.md "Security and
// limits".
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

// Only the page's own files, no inline script or style, nothing from or to elsewhere: a name in
// a model file can never become script (docs/viewer.md "Security and limits"). index.html and
// catalogue.html carry the same policy in a <meta> for --export, less frame-ancestors, which
// only a header can set; viewer/test/security.test.mjs checks that they agree.
inline constexpr const char* kContentSecurityPolicy =
    "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
    "connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'";

// What a path answers: bytes held in memory, or a model file, opened anew for each request
// and sent from that open file with the size it had then.
struct ServedFile {
  std::string path;  // "/index.html"
  std::string content_type;
  std::string_view bytes;  // unused for a model
  bool is_model = false;
  std::string disk_path;  // a model's file on disk; empty: ServerOptions::model
};

// What a path not in the fixed set answers, found when it is asked (dynpm serve): bytes made for
// the request, or a file on disk, opened then (without following a symbolic link) and sent as
// the model is.
struct Resource {
  std::string content_type;
  std::shared_ptr<const std::string> bytes;  // when `file` is empty
  std::string file;
};
// The path as the request names it (before '?'); nullopt: 404.
using Router = std::function<std::optional<Resource>(std::string_view path)>;

struct ServerOptions {
  std::vector<ServedFile> files;
  std::string model;          // the .dpm on disk
  double throttle_bytes = 0;  // bytes per second for the model; 0: as fast as it goes
  std::string content_security_policy = kContentSecurityPolicy;
  Router route;  // for the paths `files` does not hold, if set
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

// Blocks SIGINT and SIGTERM in this thread (and those it starts), so that serve() reads them.
void block_stop_signals();

// --port's value: a whole number in 0…65535 (0: any free port), or a message naming the flag.
Result<int> parse_port(const std::string& value);

}  // namespace dynpm::cli
