# The real-looking asset set (issue 11 item 7). scripts/fetch-test-data.sh (the CTest fixture
# fetch_test_data) builds it with tests/assets/build_assets.mjs into .cache/assets beside the
# test data; tests/api/asset_set_test.cpp (globbed into api_tests) cuts every asset whole.
# asset_set_built checks that the set on disk is the current builder's and that every asset
# is still valid glTF with the faces and unused objects its manifest records.
if(SEAM_NODE)
  get_filename_component(SEAM_ASSETS_DIR "${SEAM_TEST_DATA_DIR}/../assets" ABSOLUTE)
  add_test(NAME asset_set_built
           COMMAND ${SEAM_NODE} ${CMAKE_CURRENT_LIST_DIR}/build_assets.mjs --check
                   ${SEAM_TEST_DATA_DIR}/meshes ${SEAM_ASSETS_DIR})
  set_tests_properties(asset_set_built PROPERTIES FIXTURES_REQUIRED seam_test_data TIMEOUT 120)
endif()
