# Run by ctest after the tests (CTEST_CUSTOM_POST_TEST, written by
# tests/CMakeLists.txt): ctest lists skipped tests without their reasons, so
# every skipping test leaves one line in SKIP_DIR and this prints them.
file(GLOB _files "${SKIP_DIR}/*.txt")
list(LENGTH _files _n)
if(_n GREATER 0)
  message(NOTICE "Skipped tests and why:")
  list(SORT _files)
  foreach(_f ${_files})
    get_filename_component(_name "${_f}" NAME_WE)
    file(READ "${_f}" _why)
    string(STRIP "${_why}" _why)
    message(NOTICE "  ${_name}: ${_why}")
  endforeach()
endif()
