# `raildyn hertz` and `raildyn creep`: contact mechanics calculators (included from
# runner/CMakeLists.txt).
raildyn_fortran_library(rd_cmd_contact_mechanics
  ${CMAKE_CURRENT_LIST_DIR}/rd_cmd_hertz.f90
  ${CMAKE_CURRENT_LIST_DIR}/rd_cmd_creep.f90
  DEPENDS rd_contact_tangential rd_contact_normal rd_common)
