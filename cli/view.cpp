// dynpm view: serves the browser viewer (viewer/, compiled in) and one .dpm on 127.0.0.1, or
// writes the same files to a folder that any static web server can host.
//
// The .dpm is sent as it is, read from disk piece by piece: the page parses chunks as they
// arrive, so the base mesh shows before the splits have come (docs/viewer.md).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "args.h"
#include "assets.h"
#include "commands.h"

#if DYNPM_HAVE_HTTPLIB
#include <httplib.h>
#endif

namespace dynpm::cli {
namespace {

namespace fs = std::filesystem;

const VerbSpec kSpec{
    "view",
    "dynpm view MODEL.dpm [--port P] [--throttle KIB] | dynpm view MODEL.dpm --export DIR",
    "Serves a browser viewer for a .dpm on http://127.0.0.1:P/ (default port 8765; 0 picks a\n"
    "free one) until Ctrl-C: a time slider with play/pause, a resolution slider, element\n"
    "edges, colour by part or displacement. The page streams the file and refines as it\n"
    "arrives. --export writes the page, its modules and the .dpm to DIR instead, for any\n"
    "static web server.",
    {{"--port", "", true, "P", "port on 127.0.0.1 (default 8765, 0: any free port)"},
     {"--export", "", true, "DIR", "write a static folder instead of serving"},
     {"--throttle", "", true, "KIB",
      "send the .dpm at most KIB KiB per second (to watch progressive loading)"}}};

// The names the page asks for (viewer/src/viewer.js).
constexpr const char* kModelPath = "model.dpm";
constexpr const char* kConfigPath = "dpm.json";

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", c);
      out += escape;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

std::string config_json(const fs::path& model) {
  return "{\"file\": " + json_string(kModelPath) +
         ", \"name\": " + json_string(model.filename().string()) + "}\n";
}

// A .dpm opens with the PNG-style magic (docs/FORMAT.md); anything else is refused here rather
// than in the browser.
Status check_model(const fs::path& model, uintmax_t& size) {
  std::ifstream in(model, std::ios::binary);
  if (!in) return Status::error(model.string() + ": cannot open");
  char magic[8] = {};
  in.read(magic, sizeof magic);
  static constexpr unsigned char kMagic[8] = {0x89, 'D', 'P', 'M', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() != 8 || !std::equal(magic, magic + 8, kMagic, [](char a, unsigned char b) {
        return static_cast<unsigned char>(a) == b;
      }))
    return Status::error(model.string() + ": not a .dpm file (see dynpm build)");
  std::error_code error;
  size = fs::file_size(model, error);
  if (error) return Status::error(model.string() + ": " + error.message());
  return Status();
}

Status write_text(const fs::path& path, std::string_view bytes) {
  return write_file_atomically(path.string(), bytes);
}

// The model is copied under a temporary name and renamed: a partial copy would read as a
// valid, coarser model (a .dpm prefix is one).
Status copy_model(const fs::path& model, const fs::path& target) {
  remove_stale_temporaries(target.string());
  const fs::path temp = target.string() + ".tmp-" + std::to_string(::getpid()) + "-0";
  std::error_code error;
  fs::copy_file(model, temp, fs::copy_options::overwrite_existing, error);
  if (!error) fs::rename(temp, target, error);
  if (!error) return Status();
  fs::remove(temp);
  return Status::error(target.string() + ": " + error.message());
}

int export_folder(const fs::path& model, const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    std::cerr << "dynpm view: " << dir.string() << ": " << error.message() << "\n";
    return kExitFailure;
  }
  for (const viewer::Asset& asset : viewer::assets()) {
    const fs::path path = dir / fs::path(std::string(asset.path));
    fs::create_directories(path.parent_path(), error);
    Status s = error ? Status::error(path.parent_path().string() + ": " + error.message())
                     : write_text(path, asset.bytes);
    if (!s.ok()) {
      std::cerr << "dynpm view: " << s.message() << "\n";
      return kExitFailure;
    }
  }
  Status s = write_text(dir / kConfigPath, config_json(model));
  if (s.ok()) s = copy_model(model, dir / kModelPath);
  if (!s.ok()) {
    std::cerr << "dynpm view: " << s.message() << "\n";
    return kExitFailure;
  }
  std::cout << "wrote " << (dir / "index.html").string() << " with " << viewer::assets().size()
            << " files and " << kModelPath << "; serve the folder with any web server, e.g.\n"
            << "  python3 -m http.server -d " << dir.string() << "\n";
  return kExitOk;
}

#if DYNPM_HAVE_HTTPLIB
int serve(const fs::path& model, uintmax_t model_size, int port, double throttle_kib) {
  // Ctrl-C and SIGTERM are taken by sigwait() below, not by a handler: blocked before the
  // server's threads start, so they inherit the mask and the main thread alone receives them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  ::signal(SIGPIPE, SIG_IGN);  // a browser that closes mid-file must not end the server

  httplib::Server server;
  const std::string config = config_json(model);
  server.set_pre_routing_handler([](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");  // a rebuilt .dpm shows on reload
    return httplib::Server::HandlerResponse::Unhandled;
  });
  for (const viewer::Asset& asset : viewer::assets()) {
    auto handler = [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.bytes.data(), asset.bytes.size(),
                      std::string(asset.content_type).c_str());
    };
    server.Get(std::string("/").append(asset.path), handler);
    if (asset.path == "index.html") server.Get("/", handler);
  }
  server.Get(std::string("/") + kConfigPath,
             [&config](const httplib::Request&, httplib::Response& res) {
               res.set_content(config, "application/json");
             });
  server.Get(std::string("/") + kModelPath, [&](const httplib::Request&, httplib::Response& res) {
    auto file = std::make_shared<std::ifstream>(model, std::ios::binary);
    if (!*file) {
      res.status = 500;
      return;
    }
    const auto start = std::chrono::steady_clock::now();
    res.set_content_provider(
        static_cast<size_t>(model_size), "application/octet-stream",
        [file, start, throttle_kib](size_t offset, size_t length, httplib::DataSink& sink) {
          // Pieces of 64 KiB; with --throttle, paced so that offset/elapsed stays at the rate.
          std::vector<char> piece(std::min<size_t>(length, 64 * 1024));
          if (throttle_kib > 0) {
            const auto due = start + std::chrono::duration<double>(static_cast<double>(offset) /
                                                                   (throttle_kib * 1024));
            std::this_thread::sleep_until(due);
            piece.resize(std::min(piece.size(), static_cast<size_t>(throttle_kib * 1024 / 10) + 1));
          }
          file->seekg(static_cast<std::streamoff>(offset));
          file->read(piece.data(), static_cast<std::streamsize>(piece.size()));
          if (file->gcount() <= 0) return false;
          return sink.write(piece.data(), static_cast<size_t>(file->gcount()));
        });
  });

  const char* host = "127.0.0.1";
  if (port == 0) {
    port = server.bind_to_any_port(host);
    if (port < 0) {
      std::cerr << "dynpm view: cannot listen on " << host << "\n";
      return kExitFailure;
    }
  } else if (!server.bind_to_port(host, port)) {
    std::cerr << "dynpm view: cannot listen on " << host << ":" << port
              << " (in use? --port 0 picks a free one)\n";
    return kExitFailure;
  }
  std::thread listener([&server] { server.listen_after_bind(); });
  std::cout << "dynpm view: " << model.filename().string() << " (" << model_size / 1024
            << " KiB) at http://" << host << ":" << port << "/  (Ctrl-C stops)" << std::endl;
  if (!viewer::assets_complete())
    std::cerr << "warning: dynpm was built without viewer/node_modules; the page cannot draw "
                 "(run 'npm ci' in viewer/ and rebuild)\n";
  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  server.stop();
  listener.join();
  std::cout << "dynpm view: stopped" << std::endl;
  return kExitOk;
}
#endif

}  // namespace

int run_view(std::span<char* const> arguments) {
  Args args;
  if (auto exit = parse_verb_args(arguments, kSpec, args)) return *exit;
  if (args.positional.size() != 1) {
    std::cerr << "dynpm view: expected one .dpm file\n\n" << help_text(kSpec);
    return kExitUsage;
  }
  const fs::path model = args.positional.front();
  uintmax_t model_size = 0;
  if (Status s = check_model(model, model_size); !s.ok()) {
    std::cerr << "dynpm view: " << s.message() << "\n";
    return kExitFailure;
  }
  if (auto dir = args.value("--export")) return export_folder(model, *dir);

  int port = 8765;
  double throttle_kib = 0;
  try {
    if (auto p = args.value("--port")) {
      size_t used = 0;
      port = std::stoi(*p, &used);
      if (used != p->size() || port < 0 || port > 65535) throw std::invalid_argument(*p);
    }
    if (auto t = args.value("--throttle")) {
      size_t used = 0;
      throttle_kib = std::stod(*t, &used);
      if (used != t->size() || !(throttle_kib > 0)) throw std::invalid_argument(*t);
    }
  } catch (const std::exception&) {
    std::cerr << "dynpm view: --port takes 0…65535 and --throttle a positive number of KiB\n";
    return kExitUsage;
  }
#if DYNPM_HAVE_HTTPLIB
  return serve(model, model_size, port, throttle_kib);
#else
  (void)port;
  std::cerr << "dynpm view: built without cpp-httplib (Debian: libcpp-httplib-dev); use --export "
               "DIR and any web server\n";
  return kExitFailure;
#endif
}

}  // namespace dynpm::cli
