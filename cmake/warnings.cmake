# gapfe_warnings(target): strict warnings on gapfe's own executables, never on the INTERFACE target.
# Eigen and doctest come in through imported targets, hence as -isystem, so their own warnings stay out.
function(gapfe_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    # clang's -Wconversion also turns on -Wsign-conversion, which g++'s leaves off; keep the two compilers
    # to one rule (gapfe indexes std containers with int, as Eigen does).
    target_compile_options(${target} PRIVATE -Wno-sign-conversion)
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    # g++ 12 reports false stringop-overflow / restrict positives inside std::string concatenation at -O2
    # (GCC bugs 105329, 105651, 107852); they are in libstdc++, not in our code.
    target_compile_options(${target} PRIVATE -Wno-stringop-overflow -Wno-restrict -Wno-array-bounds)
  endif()
  if(GAPFE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(GAPFE_NATIVE)
    # g++ 12 flags Eigen's AVX-512 packet code (avx512fintrin.h '__Y' used uninitialized): false positives.
    target_compile_options(${target} PRIVATE -march=native -Wno-uninitialized)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")  # clang has no -Wmaybe-uninitialized
      target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
    endif()
  endif()
  if(GAPFE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=all -D_GLIBCXX_ASSERTIONS
                                             -DEIGEN_INITIALIZE_MATRICES_BY_NAN)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()
