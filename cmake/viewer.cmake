# The browser viewer of `linx view` (viewer/, docs/visualization.md).
#
# At build time: npm installs the pinned packages of viewer/package-lock.json into the BUILD tree
# (${CMAKE_BINARY_DIR}/viewer/node_modules, never the source tree), esbuild bundles the page and
# three.js into one self-contained HTML file, and viewer/build.mjs writes it as a byte array into a
# generated C++ file compiled into linx. At run time `linx view` needs no network and no file
# besides the binary and the run folder. The page is rebuilt only when viewer/ changes, and npm
# runs again only when package.json or package-lock.json change.
#
# Also serves cpp-httplib (Debian libcpp-httplib-dev, found by pkg-config) to linx_cli, and sets
# LINX_VIEWER_NODE_MODULES for the end-to-end test (tests/viewer_e2e.cmake).

find_program(LINX_NODE node)
find_program(LINX_NPM npm)
if(NOT LINX_NODE OR NOT LINX_NPM)
  message(FATAL_ERROR "linx view: node and npm are needed to build the browser viewer (viewer/); "
    "run scripts/install-deps.sh, or configure with -DLINX_BUILD_APPS=OFF")
endif()

find_package(PkgConfig REQUIRED)
pkg_check_modules(CPP_HTTPLIB IMPORTED_TARGET cpp-httplib)
if(NOT CPP_HTTPLIB_FOUND)
  message(FATAL_ERROR "linx view: cpp-httplib not found (pkg-config cpp-httplib); run "
    "scripts/install-deps.sh (Debian package libcpp-httplib-dev)")
endif()

set(LINX_VIEWER_SOURCE_DIR ${PROJECT_SOURCE_DIR}/viewer)
set(LINX_VIEWER_BINARY_DIR ${CMAKE_BINARY_DIR}/viewer)
set(LINX_VIEWER_NODE_MODULES ${LINX_VIEWER_BINARY_DIR}/node_modules)
file(MAKE_DIRECTORY ${LINX_VIEWER_BINARY_DIR})

# npm ci into the build tree, from the lock file. --ignore-scripts: no package needs its install
# script (esbuild finds its platform binary, an optional dependency, without it).
set(_linx_npm_stamp ${LINX_VIEWER_BINARY_DIR}/npm-ci.stamp)
add_custom_command(
  OUTPUT ${_linx_npm_stamp}
  COMMAND ${CMAKE_COMMAND} -E copy_if_different ${LINX_VIEWER_SOURCE_DIR}/package.json
          ${LINX_VIEWER_SOURCE_DIR}/package-lock.json ${LINX_VIEWER_BINARY_DIR}
  COMMAND ${LINX_NPM} ci --no-audit --no-fund --ignore-scripts --loglevel=error
  COMMAND ${CMAKE_COMMAND} -E touch ${_linx_npm_stamp}
  DEPENDS ${LINX_VIEWER_SOURCE_DIR}/package.json ${LINX_VIEWER_SOURCE_DIR}/package-lock.json
  WORKING_DIRECTORY ${LINX_VIEWER_BINARY_DIR}
  COMMENT "Installing the viewer's npm packages (npm ci)"
  VERBATIM)

# Bundle the page and embed it.
file(GLOB _linx_viewer_sources CONFIGURE_DEPENDS
  ${LINX_VIEWER_SOURCE_DIR}/index.html ${LINX_VIEWER_SOURCE_DIR}/*.css
  ${LINX_VIEWER_SOURCE_DIR}/src/*.js)
set(_linx_viewer_page ${LINX_VIEWER_BINARY_DIR}/index.html)
set(_linx_viewer_cpp ${LINX_VIEWER_BINARY_DIR}/viewer_page.cpp)
add_custom_command(
  OUTPUT ${_linx_viewer_page} ${_linx_viewer_cpp}
  COMMAND ${LINX_NODE} ${LINX_VIEWER_SOURCE_DIR}/build.mjs ${LINX_VIEWER_SOURCE_DIR}
          ${LINX_VIEWER_NODE_MODULES} ${_linx_viewer_page} ${_linx_viewer_cpp}
  DEPENDS ${_linx_npm_stamp} ${_linx_viewer_sources} ${LINX_VIEWER_SOURCE_DIR}/build.mjs
  COMMENT "Bundling the viewer page (esbuild) and embedding it"
  VERBATIM)
add_custom_target(linx_viewer_page DEPENDS ${_linx_viewer_page} ${_linx_viewer_cpp})

target_sources(linx_cli PRIVATE ${_linx_viewer_cpp})
add_dependencies(linx_cli linx_viewer_page)
target_link_libraries(linx_cli PRIVATE PkgConfig::CPP_HTTPLIB)
