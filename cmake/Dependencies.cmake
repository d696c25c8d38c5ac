# Every dependency is a Debian package; scripts/install-deps.sh installs them.
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(antlr4-runtime REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(IPOPT REQUIRED IMPORTED_TARGET ipopt)
# MATLAB .mat files (v4, v5, v7.3): result files and measurements (libmatio-dev).
pkg_check_modules(MATIO REQUIRED IMPORTED_TARGET matio)

find_program(ANTLR4_TOOL antlr4 REQUIRED)

# SUNDIALS' CMake package refers to static libraries Debian does not ship;
# the libraries and headers are found directly instead.
find_path(SUNDIALS_INCLUDE_DIR cvodes/cvodes.h REQUIRED)
foreach(lib cvodes idas nvecserial sunlinsoldense sunmatrixdense sunlinsolklu sunmatrixsparse)
  find_library(SUNDIALS_${lib}_LIBRARY sundials_${lib})
endforeach()
add_library(mo_sundials INTERFACE)
# KLU (SuiteSparse; libsuitesparse-dev) is the sparse linear solver of large
# simulations (runtime/src/cvode_jacobian.hpp); sunlinsol_klu.h includes klu.h.
find_path(KLU_INCLUDE_DIR klu.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(KLU_LIBRARY klu REQUIRED)
target_include_directories(mo_sundials SYSTEM INTERFACE ${SUNDIALS_INCLUDE_DIR} ${KLU_INCLUDE_DIR})
target_link_libraries(mo_sundials INTERFACE
  ${SUNDIALS_cvodes_LIBRARY} ${SUNDIALS_idas_LIBRARY} ${SUNDIALS_nvecserial_LIBRARY}
  ${SUNDIALS_sunlinsoldense_LIBRARY} ${SUNDIALS_sunmatrixdense_LIBRARY}
  ${SUNDIALS_sunlinsolklu_LIBRARY} ${SUNDIALS_sunmatrixsparse_LIBRARY} ${KLU_LIBRARY})

set(MO_ANTLR4_INCLUDE_DIR /usr/include/antlr4-runtime CACHE PATH "ANTLR4 C++ runtime headers")
add_library(mo_antlr4 INTERFACE)
target_include_directories(mo_antlr4 SYSTEM INTERFACE ${MO_ANTLR4_INCLUDE_DIR})
target_link_libraries(mo_antlr4 INTERFACE antlr4_shared)

if(MO_BUILD_TESTS)
  find_package(Catch2 2 REQUIRED)
  include(Catch)
endif()
