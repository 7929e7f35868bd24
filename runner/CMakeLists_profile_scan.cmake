# `raildyn profile-scan`: contact characteristics and equivalent conicity, and `raildyn
# conicity`: EN 15302 conicity of a given Delta r function (included from
# runner/CMakeLists.txt). rd_json (JSON strings) is here so that the commands and the runner
# share it.
raildyn_fortran_library(rd_cmd_profile_scan
  ${CMAKE_CURRENT_LIST_DIR}/rd_cmd_profile_scan.f90
  ${CMAKE_CURRENT_LIST_DIR}/rd_cmd_conicity.f90
  ${CMAKE_CURRENT_LIST_DIR}/rd_profile_curves_csv.f90
  ${CMAKE_CURRENT_LIST_DIR}/rd_json.f90
  DEPENDS rd_contact_geometry rd_hdf5 rd_model rd_common)
