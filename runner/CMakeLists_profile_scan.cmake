# `raildyn profile-scan`: contact characteristics and equivalent conicity (included from
# runner/CMakeLists.txt).
raildyn_fortran_library(rd_cmd_profile_scan
  ${CMAKE_CURRENT_LIST_DIR}/rd_cmd_profile_scan.f90
  DEPENDS rd_contact_geometry rd_hdf5 rd_model rd_common)
