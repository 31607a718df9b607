# The viewer's page and its vendored modules, compiled into a target `dynpm_viewer_assets`
# (viewer/embed/assets.h). Included from cli/CMakeLists.txt.
#
# three.js and fzstd come from viewer/node_modules (`npm ci` in viewer/, which ./dynpm.sh runs).
# Without them the build still succeeds: the vendored modules become stubs that make the page
# say what to run, and `dynpm view` warns.
set(_viewer ${PROJECT_SOURCE_DIR}/viewer)
set(_modules ${_viewer}/node_modules)

file(GLOB _page CONFIGURE_DEPENDS RELATIVE ${_viewer} ${_viewer}/index.html ${_viewer}/catalogue.html ${_viewer}/src/*.js
     ${_viewer}/src/dpm/*.js ${_viewer}/src/*.css)
set(_assets)
set(_files)
foreach(_p IN LISTS _page)
  list(APPEND _assets "${_p}=${_viewer}/${_p}")
  list(APPEND _files ${_viewer}/${_p})
endforeach()

# URL path under vendor/ → file in node_modules (_imports below maps the page's imports here).
set(_vendor
    "three.module.js=three/build/three.module.js"
    "three.core.js=three/build/three.core.js"
    "OrbitControls.js=three/examples/jsm/controls/OrbitControls.js"
    "fzstd.js=fzstd/esm/index.mjs"
    "three.LICENSE.txt=three/LICENSE"
    "fzstd.LICENSE.txt=fzstd/LICENSE")
set(_complete 1)
foreach(_v IN LISTS _vendor)
  string(REPLACE "=" ";" _pair ${_v})
  list(GET _pair 0 _name)
  list(GET _pair 1 _file)
  if(EXISTS ${_modules}/${_file})
    list(APPEND _assets "vendor/${_name}=${_modules}/${_file}")
    list(APPEND _files ${_modules}/${_file})
  else()
    set(_complete 0)
  endif()
endforeach()
if(NOT _complete)
  message(WARNING "viewer/node_modules is missing (run 'npm ci' in viewer/): dynpm view will "
                  "serve a page without three.js")
  set(_stub ${CMAKE_CURRENT_BINARY_DIR}/viewer_missing_module.js)
  file(WRITE ${_stub} "throw new Error('dynpm was built without viewer/node_modules: "
                      "run npm ci in viewer/ and rebuild');\n")
  foreach(_name three.module.js three.core.js OrbitControls.js fzstd.js)
    list(APPEND _assets "vendor/${_name}=${_stub}")
  endforeach()
  list(APPEND _files ${_stub})
endif()

# Bare module specifiers in the page's and the vendored modules → the asset they name; the
# embed tool rewrites them to relative paths (no import map: the page allows no inline script).
set(_imports
    "import:three=vendor/three.module.js"
    "import:three/addons/controls/OrbitControls.js=vendor/OrbitControls.js"
    "import:fzstd=vendor/fzstd.js")

add_executable(dynpm_embed_assets ${_viewer}/embed/embed_assets.cpp)
set(_generated ${CMAKE_CURRENT_BINARY_DIR}/viewer_assets.cpp)
add_custom_command(
  OUTPUT ${_generated}
  COMMAND dynpm_embed_assets ${_generated} ${_complete} ${_imports} ${_assets}
  DEPENDS dynpm_embed_assets ${_files}
  COMMENT "Embedding the viewer's page and modules"
  VERBATIM)
add_library(dynpm_viewer_assets STATIC ${_generated})
target_include_directories(dynpm_viewer_assets PUBLIC ${_viewer}/embed)
target_compile_features(dynpm_viewer_assets PUBLIC cxx_std_20)
