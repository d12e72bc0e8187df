# `linx view` end to end (tests/viewer_e2e.mjs): records runs, serves one, and drives the page in
# headless Chromium with playwright-core from the build tree's viewer/node_modules (installed by
# cmake/viewer.cmake). Needs the Debian package chromium (scripts/install-deps.sh); fails with a
# message saying so when it is missing. Screenshots go to ${CMAKE_CURRENT_BINARY_DIR}/viewer-e2e.
add_test(NAME viewer.e2e
  COMMAND ${LINX_NODE} ${CMAKE_CURRENT_SOURCE_DIR}/viewer_e2e.mjs $<TARGET_FILE:linx_cli>
          ${PROJECT_SOURCE_DIR}/examples ${CMAKE_CURRENT_BINARY_DIR}/viewer-e2e)
set_tests_properties(viewer.e2e PROPERTIES
  TIMEOUT 90
  ENVIRONMENT "LINX_VIEWER_NODE_MODULES=${LINX_VIEWER_NODE_MODULES}")
