# The viewer's tests (included by tests/CMakeLists.txt). They need Node.js and web/node_modules
# (`npm ci --prefix web`, which scripts/install-deps.sh runs); the browser test also needs
# Debian's chromium and reports SKIP (exit 77) when /usr/bin/chromium is missing.
set(_web_dir ${PROJECT_SOURCE_DIR}/web)
find_program(SEAM_NODE node)
if(NOT SEAM_NODE)
  message(STATUS "web tests: node not found, viewer and OpenAPI tests not registered")
  return()
endif()

# api/openapi.json: a valid OpenAPI document (swagger-parser, offline) naming every error code
# of api/error.cpp with its status and every parameter api/params.cpp accepts.
add_test(NAME web/openapi
         COMMAND ${SEAM_NODE} ${_web_dir}/tests/validate_openapi.mjs ${PROJECT_SOURCE_DIR}/api/openapi.json
                 ${PROJECT_SOURCE_DIR}/api/error.cpp ${PROJECT_SOURCE_DIR}/api/params.cpp)
set_tests_properties(web/openapi PROPERTIES TIMEOUT 60)

if(SEAM_BUILD_SERVER AND TARGET seamd)
  # The real seamd and Debian's chromium (playwright-core): sample, click, seam, screenshot.
  add_test(NAME web/viewer
           COMMAND ${SEAM_NODE} ${_web_dir}/tests/viewer.test.mjs $<TARGET_FILE:seamd> ${CMAKE_BINARY_DIR}/web-test)
  set_tests_properties(web/viewer PROPERTIES TIMEOUT 120 SKIP_RETURN_CODE 77 RUN_SERIAL ON)
endif()
