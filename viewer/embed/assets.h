// The viewer's files (viewer/index.html, viewer/src/, the vendored three.js and fzstd modules),
// compiled into the dynpm binary by viewer/embed/assets.cmake so that `dynpm view` and
// `dynpm view --export` need nothing beside the executable.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace dynpm::viewer {

struct Asset {
  std::string_view path;          // URL path and path under an export folder: "src/dpm.js"
  std::string_view content_type;  // "text/javascript; charset=utf-8"
  std::string_view bytes;
};

std::span<const Asset> assets();
// False when viewer/node_modules was missing at build time: the vendored modules are stubs that
// say so in the page.
bool assets_complete();

}  // namespace dynpm::viewer
