// dynpm serve: the catalogue of a folder of .dpm files in the browser — a page that lists them
// (viewer/catalogue.html), /index.json (the catalogue's entries, cli/catalogue.h), the files and
// their thumbnails — on 127.0.0.1, with the viewer at /view. The HTTP server is view_server.cpp,
// with its limits; this file holds what a path may name (docs/batch.md "dynpm serve").
#include <sys/stat.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include "args.h"
#include "assets.h"
#include "catalogue.h"
#include "commands.h"
#include "dynpm/progressive.h"
#include "report.h"
#include "view_server.h"

namespace dynpm::cli {
namespace {

namespace fs = std::filesystem;

const VerbSpec kSpec{
    "serve",
    "dynpm serve DIR [--port P]",
    "Serves the catalogue of every .dpm below DIR on http://127.0.0.1:P/ (default port 8766;\n"
    "0 picks a free one) until Ctrl-C: a page that lists them with their metadata and\n"
    "thumbnails, filters them, and opens one in the viewer or two side by side. /index.json\n"
    "holds the same entries as 'dynpm catalogue' writes, made again when the folder changes.\n"
    "Only .dpm files below DIR are served (no symbolic links, no build temporaries).",
    {{"--port", "", true, "P", "port on 127.0.0.1 (default 8766, 0: any free port)"}}};

// URL paths (viewer/src/catalogue.js builds them).
constexpr std::string_view kFiles = "/files/", kThumbs = "/thumb/";

// The catalogue's entries, each made again only when its file changed (size or time), and the
// index made again only when the folder's listing changed: a page that polls costs one walk
// of the folder and a stat per file.
class Catalogue {
 public:
  explicit Catalogue(std::string dir) : dir_(std::move(dir)) {}

  std::shared_ptr<const std::string> index() {
    const std::vector<std::string> files = catalogue_files(dir_);
    std::string listing;
    std::map<std::string, Stamp> stamps;
    for (const std::string& relative : files) {
      const Stamp s = stamp(relative);
      listing += relative + '\0' + std::to_string(s.size) + '\0' + std::to_string(s.mtime) + '\0';
      stamps[relative] = s;
    }
    if (index_ && listing == listing_) return index_;
    std::map<std::string, Cached> kept;
    auto entry = [&](const std::string& relative) -> Result<std::string> {
      auto it = cache_.find(relative);
      if (it == cache_.end() || it->second.stamp != stamps[relative]) {
        auto made = catalogue_entry(dir_, relative);
        Cached c{stamps[relative], made ? *made : std::string(), made ? "" : made.message()};
        it = cache_.insert_or_assign(relative, std::move(c)).first;
      }
      kept.insert(*it);
      if (!it->second.problem.empty()) return Status::error(it->second.problem);
      return it->second.entry;
    };
    CatalogueResult result;
    index_ = std::make_shared<const std::string>(catalogue_index(files, entry, result));
    cache_ = std::move(kept);  // files gone are forgotten
    listing_ = std::move(listing);
    return index_;
  }

 private:
  struct Stamp {
    uintmax_t size = 0;
    int64_t mtime = 0;  // ns
    bool operator==(const Stamp&) const = default;
  };
  struct Cached {
    Stamp stamp;
    std::string entry, problem;
  };
  Stamp stamp(const std::string& relative) const {
    struct stat s = {};
    if (::stat((fs::path(dir_) / relative).c_str(), &s) != 0) return {};
    return {static_cast<uintmax_t>(s.st_size),
            s.st_mtim.tv_sec * 1'000'000'000LL + s.st_mtim.tv_nsec};
  }

  std::string dir_;
  std::map<std::string, Cached> cache_;
  std::string listing_;
  std::shared_ptr<const std::string> index_;
};

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// The path below DIR that a URL names (after /files/): percent-decoded, then only a plain
// relative path of a .dpm — no empty, '.' or '..' segment (also when encoded: %2e%2e), no
// backslash or NUL, not a build's temporary. nullopt for anything else.
std::optional<std::string> relative_dpm(std::string_view encoded) {
  std::string path;
  for (size_t i = 0; i < encoded.size(); ++i) {
    if (encoded[i] != '%') {
      path += encoded[i];
      continue;
    }
    const int hi = i + 2 < encoded.size() ? hex_digit(encoded[i + 1]) : -1;
    const int lo = hi >= 0 ? hex_digit(encoded[i + 2]) : -1;
    if (lo < 0) return std::nullopt;
    path += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  if (path.empty() || path.find('\0') != std::string::npos || path.find('\\') != std::string::npos)
    return std::nullopt;
  for (size_t at = 0; at <= path.size();) {
    const size_t end = std::min(path.find('/', at), path.size());
    const std::string_view segment = std::string_view(path).substr(at, end - at);
    if (segment.empty() || segment == "." || segment == "..") return std::nullopt;
    at = end + 1;
  }
  const std::string name = fs::path(path).filename().string();
  if (!path.ends_with(".dpm") || name.find(".tmp-") != std::string::npos) return std::nullopt;
  return path;
}

// The file `relative` names below `root` (a canonical folder): a regular file reached without a
// symbolic link on the way, whose real path lies below root; nullopt otherwise. The server opens
// it with O_NOFOLLOW as well.
std::optional<std::string> file_below(const fs::path& root, const std::string& relative) {
  std::error_code ec;
  fs::path path = root;
  for (const fs::path& segment : fs::path(relative)) {
    path /= segment;
    if (fs::symlink_status(path, ec).type() == fs::file_type::symlink || ec) return std::nullopt;
  }
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  const fs::path real = fs::canonical(path, ec);
  if (ec || real != path) return std::nullopt;
  return path.string();
}

ServerOptions server_options(const fs::path& root, Catalogue& catalogue) {
  ServerOptions options;
  for (const viewer::Asset& asset : viewer::assets()) {
    const std::string type(asset.content_type);
    options.files.push_back({"/" + std::string(asset.path), type, asset.bytes, false, {}});
    if (asset.path == "catalogue.html")
      options.files.push_back({"/", type, asset.bytes, false, {}});
    if (asset.path == "index.html")
      options.files.push_back({"/view", type, asset.bytes, false, {}});
  }
  options.route = [root, &catalogue](std::string_view path) -> std::optional<Resource> {
    if (path == "/index.json") return Resource{"application/json", catalogue.index(), ""};
    if (path.starts_with(kFiles)) {
      const auto relative = relative_dpm(path.substr(kFiles.size()));
      const auto file = relative ? file_below(root, *relative) : std::nullopt;
      if (!file) return std::nullopt;
      return Resource{"application/octet-stream", nullptr, *file};
    }
    if (path.starts_with(kThumbs) && path.ends_with(".png")) {
      std::string dpm(path.substr(kThumbs.size()));
      dpm.replace(dpm.size() - 4, 4, ".dpm");
      const auto relative = relative_dpm(dpm);
      const auto file = relative ? file_below(root, *relative) : std::nullopt;
      auto png = file ? read_dpm_thumbnail(*file) : Status::error("");
      if (!png || !png->has_value()) return std::nullopt;  // the page shows a placeholder
      return Resource{"image/png", std::make_shared<const std::string>(std::move(**png)), ""};
    }
    return std::nullopt;
  };
  return options;
}

}  // namespace

int run_serve(std::span<char* const> arguments) {
  Args args;
  if (auto exit = parse_verb_args(arguments, kSpec, args)) return *exit;
  if (args.positional.size() != 1)
    return fail(kSpec.name, kExitUsage, "expected one folder DIR", help_text(kSpec));
  int port = 8766;
  if (auto p = args.value("--port")) {
    auto r = parse_port(*p);
    if (!r) return fail(kSpec.name, kExitUsage, r.message());
    port = *r;
  }
  const std::string dir = args.positional.front();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return fail(kSpec.name, kExitFailure, dir + ": no such folder");
  const fs::path root = fs::canonical(dir, ec);
  if (ec) return fail(kSpec.name, kExitFailure, dir + ": " + ec.message());

  block_stop_signals();  // read by the server's poll loop
  auto listener = listen_on_loopback(port);
  if (!listener) return fail(kSpec.name, kExitFailure, listener.message());
  Catalogue catalogue(root.string());
  const size_t files = catalogue_files(root.string()).size();
  catalogue.index();  // the entries made before the page asks
  std::cout << "dynpm serve: " << files << " .dpm files below " << dir
            << " at http://127.0.0.1:" << listener->port << "/  (Ctrl-C stops)" << std::endl;
  if (!viewer::assets_complete())
    std::cerr << "warning: dynpm was built without viewer/node_modules; the viewer cannot draw "
                 "(run 'npm ci' in viewer/ and rebuild)\n";
  if (Status s = serve(server_options(root, catalogue), *listener); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  std::cout << "dynpm serve: stopped" << std::endl;
  return kExitOk;
}

}  // namespace dynpm::cli
