# Compiler flags per compiler and build type. gfortran is the supported compiler; the one C
# source (src/solver/bsr_kernel.c, a kernel that needs a prefetch instruction) is built by the
# matching gcc with the same optimisation and rounding options.
set(ICTUS_FFLAGS_COMMON "")
set(ICTUS_CFLAGS_COMMON "")
set(ictus_gnu_languages "")
if(CMAKE_Fortran_COMPILER_ID STREQUAL "GNU")
  set(ICTUS_FFLAGS_COMMON -ffree-line-length-132 -fimplicit-none -std=f2018 -Wall
      -Wno-maybe-uninitialized)
  set(CMAKE_Fortran_FLAGS_DEBUG
      "-O0 -g -fbacktrace -fcheck=all -ffpe-trap=invalid,zero,overflow -finit-real=snan -finit-integer=-99999999 -finit-derived")
  list(APPEND ictus_gnu_languages Fortran)
else()
  message(WARNING "ictus is tested with gfortran only; using the compiler's default flags")
endif()
if(CMAKE_C_COMPILER_ID STREQUAL "GNU" OR CMAKE_C_COMPILER_ID STREQUAL "Clang")
  set(ICTUS_CFLAGS_COMMON -std=c11 -Wall -Wextra)
  set(CMAKE_C_FLAGS_DEBUG "-O0 -g")
  list(APPEND ictus_gnu_languages C)
endif()
foreach(lang IN LISTS ictus_gnu_languages)
  set(CMAKE_${lang}_FLAGS_RELEASE "-O3 -funroll-loops -g")
  if(ICTUS_NATIVE)
    string(APPEND CMAKE_${lang}_FLAGS_RELEASE " -march=native")
  endif()
endforeach()
# no fused multiply-adds: the reproducible sums need them off, and the C kernel must round
# exactly as the Fortran code it shares results with
if(ICTUS_DETERMINISTIC)
  if("Fortran" IN_LIST ictus_gnu_languages)
    list(APPEND ICTUS_FFLAGS_COMMON -ffp-contract=off)
  endif()
  if("C" IN_LIST ictus_gnu_languages)
    list(APPEND ICTUS_CFLAGS_COMMON -ffp-contract=off)
  endif()
endif()
