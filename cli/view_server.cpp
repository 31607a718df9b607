// The HTTP server of `dynpm view` (view_server.h): one thread, poll() over the listener, the
// connections and a signalfd for Ctrl-C.
//
// A connection reads one request head (at most kMaxHead bytes, kMaxHeaderLines lines, within
// kHeadSeconds), answers it, and then waits for the next (keep-alive) or closes. A slow or
// hostile client only holds its own buffer: nothing waits on it. Requests carry no body here; one
// that announces a body is refused and the connection closed.
#include "view_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>

#include "args.h"
#include "dynpm/text.h"

namespace dynpm::cli {
namespace {

using Clock = std::chrono::steady_clock;

// More than a browser opens (6 per host) and the 200 parallel fetches of the server test; when
// full, the connection that has waited longest for a request head makes room. Two descriptors
// each (socket, model file) stay under the usual limit of 1024.
constexpr size_t kMaxConnections = 256;
// A client that takes nothing for this long while we send is dropped.
constexpr int kSendStallSeconds = 30;
constexpr size_t kPiece = 64 * 1024;

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

struct Connection {
  int fd = -1;
  std::string in;                   // received bytes not yet parsed
  Clock::time_point waiting_since;  // for a request head, or for the client to take bytes
  bool sending = false;
  bool close_after = false;
  std::string head;  // the response's status line and headers
  size_t head_sent = 0;
  // The body: bytes in memory, or [file_at, file_end) of an open model file.
  std::string_view body;
  std::shared_ptr<const std::string> body_owner;  // a Resource's bytes, kept while sent
  size_t body_sent = 0;
  int file = -1;
  struct stat file_stat = {};
  uint64_t file_begin = 0, file_at = 0, file_end = 0;
  Clock::time_point file_start;
  std::vector<char> piece;  // read from the file, not yet sent: [piece_at, piece.size())
  size_t piece_at = 0;

  ~Connection() {
    if (file >= 0) ::close(file);
    if (fd >= 0) ::close(fd);
  }
};

// A single "bytes=" range over a body of `size` bytes: [first, last], nullopt for none (no
// header, another unit, several ranges or bad syntax are all served whole, as RFC 9110 allows),
// or `unsatisfiable`.
struct Range {
  uint64_t first = 0, last = 0;
  bool unsatisfiable = false;
};
std::optional<Range> parse_range(std::string_view value, uint64_t size) {
  value = trim_blanks(value);
  if (value.substr(0, 6) != "bytes=" || value.find(',') != std::string_view::npos)
    return std::nullopt;
  value.remove_prefix(6);
  const size_t dash = value.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  auto number = [](std::string_view s, uint64_t& n) {
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
    return !s.empty() && ec == std::errc() && end == s.data() + s.size();
  };
  const std::string_view a = value.substr(0, dash), b = value.substr(dash + 1);
  Range r;
  if (a.empty()) {  // the last n bytes
    uint64_t n = 0;
    if (!number(b, n)) return std::nullopt;
    if (n == 0 || size == 0) return Range{0, 0, true};
    r.first = size - std::min(n, size);
    r.last = size - 1;
    return r;
  }
  if (!number(a, r.first)) return std::nullopt;
  r.last = UINT64_MAX;
  if (!b.empty() && !number(b, r.last)) return std::nullopt;
  if (r.last < r.first) return std::nullopt;
  if (r.first >= size) return Range{0, 0, true};
  r.last = std::min(r.last, size - 1);
  return r;
}

class Server {
 public:
  Server(const ServerOptions& options, Listener listener)
      : options_(options), listener_(listener) {}
  ~Server() {
    if (listener_.fd >= 0) ::close(listener_.fd);
  }
  Status run();

 private:
  void accept_connections();
  void read_request(Connection& c);
  void answer(Connection& c, std::string_view head);
  void respond(Connection& c, int status, std::string_view reason, std::string_view type,
               uint64_t length, std::string_view extra_headers);
  void refuse(Connection& c, int status, std::string_view reason, bool close,
              std::string_view extra_headers = "");
  bool write_response(Connection& c);  // false: close the connection
  void finish_response(Connection& c);
  // When the next piece of the model may go (--throttle), or now.
  Clock::time_point file_due(const Connection& c) const;

  const ServerOptions& options_;
  Listener listener_;
  std::vector<std::unique_ptr<Connection>> connections_;
};

Status Server::run() {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  const int signals = ::signalfd(-1, &stop, SFD_CLOEXEC | SFD_NONBLOCK);
  if (signals < 0) return Status::error(std::string("signalfd: ") + std::strerror(errno));
  std::vector<pollfd> fds;
  for (;;) {
    const auto now = Clock::now();
    // Expired: a head not complete in time, a client that takes nothing.
    std::erase_if(connections_, [&](const std::unique_ptr<Connection>& c) {
      const int limit = c->sending ? kSendStallSeconds : kHeadSeconds;
      return now - c->waiting_since > std::chrono::seconds(limit) &&
             !(c->sending && c->file >= 0 && file_due(*c) > now);
    });
    fds.clear();
    fds.push_back({signals, POLLIN, 0});
    fds.push_back({listener_.fd, POLLIN, 0});
    auto wake = now + std::chrono::seconds(1);
    for (const auto& c : connections_) {
      short events = c->sending ? POLLOUT : POLLIN;
      if (c->sending && c->head_sent == c->head.size() && c->file >= 0 &&
          c->piece_at == c->piece.size()) {
        const auto due = file_due(*c);
        if (due > now) events = 0, wake = std::min(wake, due);
      }
      fds.push_back({c->fd, events, 0});
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(wake - now);
    if (::poll(fds.data(), fds.size(), static_cast<int>(wait.count()) + 1) < 0) {
      if (errno == EINTR) continue;
      ::close(signals);
      return Status::error(std::string("poll: ") + std::strerror(errno));
    }
    if (fds[0].revents) break;
    for (size_t i = 0; i < connections_.size(); ++i) {
      Connection& c = *connections_[i];
      const pollfd& p = fds[i + 2];
      const bool paused = p.events == 0;  // throttled: its time may have come
      bool keep = !(p.revents & (POLLERR | POLLNVAL));
      if (keep && c.sending && (p.revents & POLLOUT || paused))
        keep = write_response(c);
      else if (keep && !c.sending && p.revents & (POLLIN | POLLHUP))
        read_request(c);
      if (!keep) {
        c.close_after = true;
        c.sending = false;
      }
    }
    std::erase_if(connections_, [](const std::unique_ptr<Connection>& c) {
      return c->fd < 0 || (c->close_after && !c->sending);
    });
    if (fds[1].revents & POLLIN) accept_connections();
  }
  ::close(signals);
  connections_.clear();
  return Status();
}

void Server::accept_connections() {
  for (;;) {
    const int fd = ::accept4(listener_.fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN, or a client gone already: nothing to do
    if (connections_.size() >= kMaxConnections) {
      // Full: the connection idle or slowest on its head longest goes first.
      auto oldest = std::min_element(connections_.begin(), connections_.end(),
                                     [](const auto& a, const auto& b) {
                                       return std::pair(a->sending, a->waiting_since) <
                                              std::pair(b->sending, b->waiting_since);
                                     });
      if ((*oldest)->sending) {
        ::close(fd);
        continue;
      }
      connections_.erase(oldest);
    }
    auto c = std::make_unique<Connection>();
    c->fd = fd;
    c->waiting_since = Clock::now();
    connections_.push_back(std::move(c));
  }
}

void Server::read_request(Connection& c) {
  char buffer[4096];
  const ssize_t n = ::recv(c.fd, buffer, sizeof buffer, 0);
  if (n <= 0) {
    if (n == 0 || (errno != EAGAIN && errno != EINTR)) c.close_after = true;
    return;
  }
  c.in.append(buffer, static_cast<size_t>(n));
  const size_t end = c.in.find("\r\n\r\n");
  if (end == std::string::npos) {
    if (c.in.size() > kMaxHead) refuse(c, 431, "Request Header Fields Too Large", true);
    return;
  }
  if (end + 4 > kMaxHead) return refuse(c, 431, "Request Header Fields Too Large", true);
  const std::string head = c.in.substr(0, end + 2);
  c.in.erase(0, end + 4);
  answer(c, head);
}

// `head`: the request line and header lines, each ending in CRLF.
void Server::answer(Connection& c, std::string_view head) {
  std::vector<std::string_view> lines;
  for (size_t at = 0; at < head.size();) {
    const size_t eol = head.find("\r\n", at);
    lines.push_back(head.substr(at, eol - at));
    at = eol + 2;
  }
  if (lines.size() - 1 > kMaxHeaderLines)
    return refuse(c, 431, "Request Header Fields Too Large", true);
  // "GET /path HTTP/1.1"
  const std::string_view line = lines[0];
  const size_t sp1 = line.find(' '), sp2 = line.rfind(' ');
  if (sp1 == std::string_view::npos || sp2 == sp1) return refuse(c, 400, "Bad Request", true);
  const std::string_view method = line.substr(0, sp1), version = line.substr(sp2 + 1);
  std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return refuse(c, 400, "Bad Request", true);
  c.close_after = version == "HTTP/1.0";

  std::optional<std::string_view> host, range;
  for (size_t i = 1; i < lines.size(); ++i) {
    const size_t colon = lines[i].find(':');
    if (colon == 0 || colon == std::string_view::npos || lines[i][0] == ' ' || lines[i][0] == '\t')
      return refuse(c, 400, "Bad Request", true);
    const std::string_view name = lines[i].substr(0, colon),
                           value = trim_blanks(lines[i].substr(colon + 1));
    if (iequals(name, "host")) {
      if (host) return refuse(c, 400, "Bad Request", true);
      host = value;
    } else if (iequals(name, "range")) {
      range = value;
    } else if (iequals(name, "connection")) {
      if (value.find("close") != std::string_view::npos) c.close_after = true;
    } else if (iequals(name, "transfer-encoding") ||
               (iequals(name, "content-length") && value != "0")) {
      return refuse(c, 400, "Bad Request", true);  // no request here has a body
    }
  }
  // DNS rebinding: a page of another site whose name now points at 127.0.0.1 sends its own
  // name as Host. Only our own names, with our port, are served.
  if (!host) return refuse(c, 400, "Bad Request", true);
  const std::string port = ":" + std::to_string(listener_.port);
  bool ours = false;
  for (std::string_view name : {"127.0.0.1", "localhost", "[::1]"})
    ours = ours || iequals(*host, std::string(name) + port);
  if (!ours) return refuse(c, 403, "Forbidden", c.close_after);

  if (method != "GET" && method != "HEAD")
    return refuse(c, 405, "Method Not Allowed", c.close_after, "Allow: GET, HEAD\r\n");
  target = target.substr(0, target.find_first_of("?#"));
  const auto file = std::find_if(options_.files.begin(), options_.files.end(),
                                 [&](const ServedFile& f) { return f.path == target; });
  std::optional<Resource> routed;
  if (file == options_.files.end() && options_.route) routed = options_.route(target);
  if (file == options_.files.end() && !routed) return refuse(c, 404, "Not Found", c.close_after);
  const std::string content_type = routed ? routed->content_type : file->content_type;
  std::string_view bytes;
  std::string disk;  // the file to send, opened for this request
  if (!routed) {
    bytes = file->bytes;
    if (file->is_model) disk = file->disk_path.empty() ? options_.model : file->disk_path;
  } else if (routed->file.empty()) {
    c.body_owner = routed->bytes;
    bytes = *c.body_owner;
  } else {
    disk = routed->file;
  }

  uint64_t size = bytes.size();
  if (!disk.empty()) {
    // Opened for this request: a model rebuilt since (dynpm writes a new file and renames it)
    // is sent whole with its new size; one changed in place while sent is cut off, never
    // completed with bytes of another file.
    // A routed file's folders were checked for links when routed (serve); its last name is checked
    // here. The models `dynpm view` was given are opened as named.
    c.file = ::open(disk.c_str(), O_RDONLY | O_CLOEXEC | (routed ? O_NOFOLLOW : 0));
    if (c.file >= 0 && (::fstat(c.file, &c.file_stat) != 0 || !S_ISREG(c.file_stat.st_mode)))
      ::close(c.file), c.file = -1;
    if (c.file < 0)
      return refuse(c, 500, "Internal Server Error: the file cannot be read", c.close_after);
    size = static_cast<uint64_t>(c.file_stat.st_size);
  }
  std::string extra = "Accept-Ranges: bytes\r\n";
  int status = 200;
  std::string_view reason = "OK";
  uint64_t first = 0, length = size;
  if (range) {
    if (auto r = parse_range(*range, size)) {
      if (r->unsatisfiable) {
        if (c.file >= 0) ::close(c.file), c.file = -1;
        extra += "Content-Range: bytes */" + std::to_string(size) + "\r\n";
        respond(c, 416, "Range Not Satisfiable", "text/plain; charset=utf-8", 0, extra);
        return;
      }
      status = 206;
      reason = "Partial Content";
      first = r->first;
      length = r->last - r->first + 1;
      extra += "Content-Range: bytes " + std::to_string(r->first) + "-" + std::to_string(r->last) +
               "/" + std::to_string(size) + "\r\n";
    }
  }
  respond(c, status, reason, content_type, length, extra);
  if (method == "HEAD") {
    if (c.file >= 0) ::close(c.file), c.file = -1;
    return;
  }
  if (c.file >= 0) {
    c.file_begin = c.file_at = first;
    c.file_end = first + length;
    c.file_start = Clock::now();
  } else {
    c.body = bytes.substr(first, length);
  }
}

void Server::respond(Connection& c, int status, std::string_view reason, std::string_view type,
                     uint64_t length, std::string_view extra_headers) {
  c.head = "HTTP/1.1 " + std::to_string(status) + " " + std::string(reason) + "\r\n";
  c.head += "Content-Type: " + std::string(type) + "\r\n";
  c.head += "Content-Length: " + std::to_string(length) + "\r\n";
  c.head += "Content-Security-Policy: " + options_.content_security_policy + "\r\n";
  c.head +=
      "X-Content-Type-Options: nosniff\r\n"
      "Referrer-Policy: no-referrer\r\n"
      "Cross-Origin-Resource-Policy: same-origin\r\n"
      // Cross-origin isolated: the decode worker shares the model's arrays with the page
      // (SharedArrayBuffer) instead of copying them (docs/viewer.md "Decoding in a worker").
      "Cross-Origin-Opener-Policy: same-origin\r\n"
      "Cross-Origin-Embedder-Policy: require-corp\r\n"
      "Cache-Control: no-store\r\n";  // a rebuilt .dpm shows on reload
  c.head += extra_headers;
  if (c.close_after) c.head += "Connection: close\r\n";
  c.head += "\r\n";
  c.head_sent = 0;
  c.body = {};  // body_owner stays: answer() set it for this response
  c.body_sent = 0;
  c.piece.clear();
  c.piece_at = 0;
  c.sending = true;
  c.waiting_since = Clock::now();
}

void Server::refuse(Connection& c, int status, std::string_view reason, bool close,
                    std::string_view extra_headers) {
  c.close_after = c.close_after || close;
  const std::string text = std::to_string(status) + " " + std::string(reason) + "\n";
  respond(c, status, reason, "text/plain; charset=utf-8", text.size(), extra_headers);
  c.head += text;  // the body goes out with the head
}

Clock::time_point Server::file_due(const Connection& c) const {
  if (options_.throttle_bytes <= 0) return Clock::time_point();
  const double seconds = static_cast<double>(c.file_at - c.file_begin) / options_.throttle_bytes;
  return c.file_start +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

bool Server::write_response(Connection& c) {
  auto send_some = [&](const char* data, size_t n) -> ssize_t {
    const ssize_t sent = ::send(c.fd, data, n, MSG_NOSIGNAL);
    if (sent > 0) c.waiting_since = Clock::now();
    return sent < 0 && (errno == EAGAIN || errno == EINTR) ? 0 : sent;
  };
  if (c.head_sent < c.head.size()) {
    const ssize_t n = send_some(c.head.data() + c.head_sent, c.head.size() - c.head_sent);
    if (n < 0) return false;
    c.head_sent += static_cast<size_t>(n);
    if (c.head_sent < c.head.size()) return true;
  }
  if (c.body_sent < c.body.size()) {
    const ssize_t n = send_some(c.body.data() + c.body_sent, c.body.size() - c.body_sent);
    if (n < 0) return false;
    c.body_sent += static_cast<size_t>(n);
    if (c.body_sent < c.body.size()) return true;
  }
  if (c.file >= 0) {
    if (c.piece_at == c.piece.size()) {
      if (c.file_at == c.file_end) {
        finish_response(c);
        return true;
      }
      if (file_due(c) > Clock::now()) return true;
      // The file must still be the one whose size went out in Content-Length.
      struct stat now = {};
      if (::fstat(c.file, &now) != 0 || now.st_size != c.file_stat.st_size ||
          now.st_mtim.tv_sec != c.file_stat.st_mtim.tv_sec ||
          now.st_mtim.tv_nsec != c.file_stat.st_mtim.tv_nsec)
        return false;
      size_t want = static_cast<size_t>(std::min<uint64_t>(kPiece, c.file_end - c.file_at));
      if (options_.throttle_bytes > 0)  // ten pieces a second
        want = std::min(want, static_cast<size_t>(options_.throttle_bytes / 10) + 1);
      c.piece.resize(want);
      const ssize_t got = ::pread(c.file, c.piece.data(), want, static_cast<off_t>(c.file_at));
      if (got != static_cast<ssize_t>(want)) return false;  // shorter than announced
      c.piece_at = 0;
      c.file_at += want;
    }
    const ssize_t n = send_some(c.piece.data() + c.piece_at, c.piece.size() - c.piece_at);
    if (n < 0) return false;
    c.piece_at += static_cast<size_t>(n);
    return true;
  }
  finish_response(c);
  return true;
}

// The response is out: close, or wait for the next request (one may have come already).
void Server::finish_response(Connection& c) {
  c.sending = false;
  if (c.file >= 0) ::close(c.file), c.file = -1;
  c.piece = {};
  c.head = {};
  c.body = {};
  c.body_owner = {};
  c.waiting_since = Clock::now();
  if (c.close_after) {
    ::shutdown(c.fd, SHUT_WR);
    return;
  }
  const size_t end = c.in.find("\r\n\r\n");
  if (end != std::string::npos && end + 4 <= kMaxHead) {
    const std::string head = c.in.substr(0, end + 2);
    c.in.erase(0, end + 4);
    answer(c, head);
  } else if (c.in.size() > kMaxHead) {
    refuse(c, 431, "Request Header Fields Too Large", true);
  }
}

}  // namespace

Result<Listener> listen_on_loopback(int port) {
  const std::string where = "127.0.0.1:" + std::to_string(port);
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return Status::error("cannot listen on " + where + ": " + std::strerror(errno));
  // SO_REUSEADDR lets a restarted server take its port while old connections linger; never
  // SO_REUSEPORT, with which a second server on the port would share the requests.
  const int yes = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in address = {};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(fd, SOMAXCONN) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) != 0) {
    const int cause = errno;
    ::close(fd);
    return Status::error("cannot listen on " + where +
                         (cause == EADDRINUSE ? " (in use? --port 0 picks a free one)"
                                              : ": " + std::string(std::strerror(cause))));
  }
  return Listener{fd, ntohs(address.sin_port)};
}

Status serve(const ServerOptions& options, Listener listener) {
  return Server(options, listener).run();
}

void block_stop_signals() {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
}

Result<int> parse_port(const std::string& value) {
  auto port = parse_whole("--port", value, 0, 65535);
  if (!port)
    return Status::error("--port takes a whole number in 0…65535 (0: any free port), not " +
                         quoted_value(value));
  return static_cast<int>(*port);
}

}  // namespace dynpm::cli
