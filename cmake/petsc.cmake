# Optional PETSc over MPI: the distributed solver policy (gapfe/solver/petsc.hpp) and the MPI
# subdomain (gapfe/solver/petsc_subdomain.hpp) for problems partitioned over several processes. PETSc ships no
# CMake package, so it is found through pkg-config (PETSc.pc; Debian's libpetsc-real-dev, or a cluster's
# module that puts its PETSc.pc on PKG_CONFIG_PATH), MPI through CMake's FindMPI. gapfe::petsc carries
# GAPFE_HAS_PETSC=1 and GAPFE_PETSC_INT_BITS (32 or 64, PETSc's PetscInt, which the header checks against
# the PETSc it is compiled with). The library proper and the default build stay free of MPI: OFF by default.
set(GAPFE_HAS_PETSC OFF)
if(GAPFE_WITH_PETSC)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc)
  find_package(MPI REQUIRED COMPONENTS CXX)
  # PETSc.pc's Cflags carry Debian's build flags (-D_FORTIFY_SOURCE=2, -Wdate-time), which are not PETSc's
  # interface and warn in an unoptimized build; only its include directory is.
  set_property(TARGET PkgConfig::PETSC PROPERTY INTERFACE_COMPILE_OPTIONS "")
  # PETSc's configuration decides what the policy can take: it must be built with real double scalars (a
  # complex PETSc would take our doubles as half-values), and its index width is recorded for the header.
  include(CheckCXXSourceCompiles)
  include(CMakePushCheckState)
  cmake_push_check_state(RESET)
  set(CMAKE_REQUIRED_INCLUDES ${PETSC_INCLUDE_DIRS} ${MPI_CXX_INCLUDE_DIRS})
  set(CMAKE_REQUIRED_QUIET ON)
  check_cxx_source_compiles("#include <petscsys.h>
    #include <type_traits>
    static_assert(std::is_same<PetscScalar, double>::value, \"real double\");
    int main() {}" GAPFE_PETSC_REAL_DOUBLE)
  check_cxx_source_compiles("#include <petscsys.h>
    static_assert(sizeof(PetscInt) == 8, \"64-bit indices\");
    int main() {}" GAPFE_PETSC_64BIT_INDICES)
  cmake_pop_check_state()
  if(NOT GAPFE_PETSC_REAL_DOUBLE)
    message(FATAL_ERROR "gapfe: the PETSc found (${PETSC_PREFIX}) does not use real double scalars; gapfe needs "
                        "a PETSc configured --with-scalar-type=real --with-precision=double (Debian: libpetsc-real-dev)")
  endif()
  if(GAPFE_PETSC_64BIT_INDICES)
    set(GAPFE_PETSC_INT_BITS 64)
  else()
    set(GAPFE_PETSC_INT_BITS 32)
  endif()
  set(GAPFE_HAS_PETSC ON)
  add_library(gapfe_petsc INTERFACE)
  add_library(gapfe::petsc ALIAS gapfe_petsc)
  target_link_libraries(gapfe_petsc INTERFACE gapfe::gapfe PkgConfig::PETSC MPI::MPI_CXX)
  target_compile_definitions(gapfe_petsc INTERFACE GAPFE_HAS_PETSC=1 GAPFE_PETSC_INT_BITS=${GAPFE_PETSC_INT_BITS})
  message(STATUS "gapfe: PETSc ${PETSC_VERSION} found (${PETSC_PREFIX}, ${GAPFE_PETSC_INT_BITS}-bit indices, MPI "
                 "${MPI_CXX_VERSION}): the PetscSolver policy and partitioned runs are enabled")
endif()
