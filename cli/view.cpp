// dynpm view: serves the browser viewer (viewer/, compiled in) and one .dpm on 127.0.0.1, or
// writes the same files to a folder that any static web server can host.
//
// The .dpm is sent as it is, read from disk piece by piece: the page parses chunks as they
// arrive, so the base mesh shows before the splits have come (docs/viewer.md). The HTTP server
// is view_server.cpp; this file holds what is served and the flags.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "args.h"
#include "assets.h"
#include "commands.h"
#include "dynpm/core.h"
#include "report.h"
#include "view_server.h"

namespace dynpm::cli {
namespace {

namespace fs = std::filesystem;

const VerbSpec kSpec{
    "view",
    "dynpm view MODEL.dpm [OTHER.dpm [--layout L]] [--port P] [--throttle KIB] | dynpm view "
    "MODEL.dpm [OTHER.dpm [--layout L]] --export DIR",
    "Serves a browser viewer for a .dpm on http://127.0.0.1:P/ (default port 8765; 0 picks a\n"
    "free one) until Ctrl-C: a time slider with play/pause, a resolution slider, element\n"
    "edges, colour by part or displacement. The page streams the file and refines as it\n"
    "arrives. With a second .dpm the page compares the two side by side, with one camera,\n"
    "time and resolution, and shows |p_A - p_B| when both hold one hierarchy; --layout edges\n"
    "or surface draws the second over the first instead. --export writes the page, its\n"
    "modules and the .dpm files to DIR instead, for any static web server.",
    {{"--port", "", true, "P", "port on 127.0.0.1 (default 8765, 0: any free port)"},
     {"--export", "", true, "DIR",
      "write a static folder instead of serving (DIR: new, empty, or an earlier export)"},
     {"--throttle", "", true, "KIB",
      "send the .dpm at most KIB KiB per second, 1…1048576 (to watch progressive loading)"},
     {"--layout", "", true, "L",
      "two models side (by side, default), or the second over the first: edges, surface"}}};

// The names the page asks for (viewer/src/viewer.js).
constexpr const char* kModelPath = "model.dpm";
constexpr const char* kConfigPath = "dpm.json";
constexpr const char* kComparePath = "compare.dpm";  // the second model, if any

// --throttle in KiB/s: at least 1 (slower only stalls the page), at most 1 GiB/s (faster is
// no throttle at all).
constexpr double kMinThrottleKib = 1, kMaxThrottleKib = 1024 * 1024;

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

// `compare`: the second model, or empty; `layout`: how the page lays the two out
// (compare_overlay.js), or empty.
std::string config_json(const fs::path& model, const fs::path& compare, const std::string& layout) {
  std::string json = "{\"file\": " + json_string(kModelPath) +
                     ", \"name\": " + json_string(model.filename().string());
  if (!compare.empty())
    json += ", \"compare\": " + json_string(kComparePath) +
            ", \"compareName\": " + json_string(compare.filename().string());
  if (!layout.empty()) json += ", \"compareLayout\": " + json_string(layout);
  return json + "}\n";
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

// What an export writes, as paths under DIR: the page's files, their folders, the
// configuration and the model.
struct ExportLayout {
  std::set<fs::path> files, folders;
};
ExportLayout export_layout() {
  ExportLayout layout;
  for (const viewer::Asset& asset : viewer::assets()) {
    const fs::path path(std::string(asset.path));
    layout.files.insert(path);
    for (fs::path p = path.parent_path(); !p.empty(); p = p.parent_path()) layout.folders.insert(p);
  }
  layout.files.insert(kConfigPath);
  layout.files.insert(kModelPath);
  layout.files.insert(kComparePath);
  return layout;
}

// DIR may be missing, empty or an earlier export (only what an export writes), which is
// replaced; anything else is refused, so that an export never deletes a file of the user's.
Status check_export_target(const fs::path& dir, bool& exists) {
  std::error_code error;
  exists = fs::exists(dir, error);
  if (error) return Status::error(dir.string() + ": " + error.message());
  if (!exists) return Status();
  if (!fs::is_directory(dir, error))
    return Status::error(dir.string() + ": exists and is not a folder");
  const ExportLayout layout = export_layout();
  for (fs::recursive_directory_iterator it(dir, error), end; !error && it != end;
       it.increment(error)) {
    const fs::path relative = it->path().lexically_relative(dir);
    const bool ours = it->is_symlink()        ? false
                      : it->is_directory()    ? layout.folders.count(relative) != 0
                      : it->is_regular_file() ? layout.files.count(relative) != 0
                                              : false;
    if (!ours)
      return Status::error(dir.string() + ": holds " + relative.string() +
                           ", so it is not an earlier export; choose a new or empty folder");
  }
  if (error) return Status::error(dir.string() + ": " + error.message());
  return Status();
}

// The page, its configuration and a copy of the model (and of the second one), in `folder`
// (which does not exist yet).
Status write_export(const fs::path& model, const fs::path& compare, const std::string& config,
                    const fs::path& folder) {
  std::error_code error;
  auto failed = [&](const fs::path& path) {
    return Status::error(path.string() + ": " + error.message());
  };
  if (!fs::create_directory(folder, error)) return failed(folder);
  for (const viewer::Asset& asset : viewer::assets()) {
    const fs::path path = folder / fs::path(std::string(asset.path));
    if (fs::create_directories(path.parent_path(), error); error) return failed(path.parent_path());
    DYNPM_RETURN_IF_ERROR(write_file_atomically(path.string(), asset.bytes));
  }
  DYNPM_RETURN_IF_ERROR(write_file_atomically((folder / kConfigPath).string(), config));
  if (!fs::copy_file(model, folder / kModelPath, error)) return failed(folder / kModelPath);
  if (!compare.empty() && !fs::copy_file(compare, folder / kComparePath, error))
    return failed(folder / kComparePath);
  return Status();
}

// Folders "<prefix><pid>-<n>" in `parent` that a killed export left: their process is gone.
void remove_stale_exports(const fs::path& parent, const std::string& prefix) {
  std::error_code error;
  for (fs::directory_iterator it(parent, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(prefix) || !it->is_directory()) continue;
    long pid = 0;
    const char* digits = name.data() + prefix.size();
    auto [after, ec] = std::from_chars(digits, name.data() + name.size(), pid);
    if (ec != std::errc() || after == digits || *after != '-' || pid == ::getpid() ||
        !process_has_ended(pid))
      continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

// Built in a temporary sibling folder and renamed into place: a failed or killed export leaves
// DIR as it was (a partial folder would show a page without its model, or a model prefix,
// which reads as a valid coarser model).
Status export_folder(const fs::path& model, const fs::path& compare, const std::string& config,
                     fs::path dir) {
  if (!dir.has_filename()) dir = dir.parent_path();  // "out/" → "out"
  bool exists = false;
  DYNPM_RETURN_IF_ERROR(check_export_target(dir, exists));
  std::error_code error;
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  // The missing ancestors are created, and removed again if the export fails.
  fs::path created;
  for (fs::path p = parent; !p.empty() && !fs::exists(p, error); p = p.parent_path()) created = p;
  if (fs::create_directories(parent, error); error)
    return Status::error(parent.string() + ": " + error.message());
  const std::string stem = dir.filename().string() + ".tmp-" + std::to_string(::getpid());
  const fs::path temp = parent / (stem + "-0"), old = parent / (stem + "-1");
  remove_stale_exports(parent, dir.filename().string() + ".tmp-");
  Status s = write_export(model, compare, config, temp);
  if (s.ok()) {
    // A missing or empty DIR is replaced by rename itself; an earlier export is moved aside
    // first, and put back if the new one cannot take its place.
    fs::rename(temp, dir, error);
    if (error && exists) {
      error.clear();
      fs::rename(dir, old, error);
      if (!error) {
        fs::rename(temp, dir, error);
        std::error_code ignored;
        if (error)
          fs::rename(old, dir, ignored);
        else
          fs::remove_all(old, ignored);
      }
    }
    if (error) s = Status::error(dir.string() + ": " + error.message());
  }
  fs::remove_all(temp, error);
  if (!s.ok() && !created.empty()) fs::remove_all(created, error);
  return s;
}

// The files the server answers for: the page's, the configuration and the model (and the
// second one).
ServerOptions server_options(const fs::path& model, const fs::path& compare,
                             const std::string& config, double throttle_kib) {
  ServerOptions options;
  for (const viewer::Asset& asset : viewer::assets()) {
    options.files.push_back(
        {"/" + std::string(asset.path), std::string(asset.content_type), asset.bytes, false, {}});
    if (asset.path == "index.html")
      options.files.push_back({"/", std::string(asset.content_type), asset.bytes, false, {}});
  }
  options.files.push_back({std::string("/") + kConfigPath, "application/json", config, false, {}});
  options.files.push_back(
      {std::string("/") + kModelPath, "application/octet-stream", {}, true, {}});
  if (!compare.empty())
    options.files.push_back(
        {std::string("/") + kComparePath, "application/octet-stream", {}, true, compare.string()});
  options.model = model.string();
  options.throttle_bytes = throttle_kib * 1024;
  return options;
}

int serve_model(const fs::path& model, const fs::path& compare, const std::string& config,
                uintmax_t model_size, int port, double throttle_kib) {
  // Ctrl-C and SIGTERM are read by the server's poll loop (a signalfd): blocked here.
  block_stop_signals();

  auto listener = listen_on_loopback(port);
  if (!listener) return fail(kSpec.name, kExitFailure, listener.message());
  std::cout << "dynpm view: " << model.filename().string() << " (" << model_size / 1024 << " KiB)"
            << (compare.empty() ? "" : " beside " + compare.filename().string())
            << " at http://127.0.0.1:" << listener->port << "/  (Ctrl-C stops)" << std::endl;
  if (!viewer::assets_complete())
    std::cerr << "warning: dynpm was built without viewer/node_modules; the page cannot draw "
                 "(run 'npm ci' in viewer/ and rebuild)\n";
  if (Status s = serve(server_options(model, compare, config, throttle_kib), *listener); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  std::cout << "dynpm view: stopped" << std::endl;
  return kExitOk;
}

}  // namespace

int run_view(std::span<char* const> arguments) {
  Args args;
  if (auto exit = parse_verb_args(arguments, kSpec, args)) return *exit;
  if (args.positional.empty() || args.positional.size() > 2)
    return fail(kSpec.name, kExitUsage, "expected one .dpm file, or two to compare",
                help_text(kSpec));
  int port = 8765;
  double throttle_kib = 0;
  // "--port abc" and "--throttle inf" each get a message that names the flag and its range.
  if (auto p = args.value("--port")) {
    auto r = parse_port(*p);
    if (!r) return fail(kSpec.name, kExitUsage, r.message());
    port = *r;
  }
  if (auto t = args.value("--throttle")) {
    auto r = parse_number("--throttle", *t, {kMinThrottleKib, kMaxThrottleKib});
    if (!r)
      return fail(kSpec.name, kExitUsage,
                  "--throttle takes KiB per second in 1…1048576, not " + quoted_value(*t));
    throttle_kib = *r;
  }
  const fs::path model = args.positional.front();
  const fs::path compare = args.positional.size() == 2 ? fs::path(args.positional[1]) : fs::path();
  const std::string layout = args.value("--layout").value_or("");
  if (!layout.empty() && compare.empty())
    return fail(kSpec.name, kExitUsage, "--layout needs a second model to lay out");
  if (!layout.empty() && layout != "side" && layout != "edges" && layout != "surface")
    return fail(kSpec.name, kExitUsage,
                "--layout is side, edges or surface, got " + quoted_value(layout));
  const std::string config = config_json(model, compare, layout);
  uintmax_t model_size = 0, compare_size = 0;
  if (Status s = check_model(model, model_size); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  if (Status s = compare.empty() ? Status() : check_model(compare, compare_size); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  if (auto dir = args.value("--export")) {
    if (Status s = export_folder(model, compare, config, *dir); !s.ok())
      return fail(kSpec.name, kExitFailure, s.message());
    std::cout << "wrote " << (fs::path(*dir) / "index.html").string() << " with "
              << viewer::assets().size() << " files and " << kModelPath
              << (compare.empty() ? "" : std::string(" and ") + kComparePath)
              << "; serve the folder with any web server, e.g.\n"
              << "  python3 -m http.server -d " << *dir << "\n";
    return kExitOk;
  }
  return serve_model(model, compare, config, model_size, port, throttle_kib);
}

}  // namespace dynpm::cli
