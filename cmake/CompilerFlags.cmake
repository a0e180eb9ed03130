# Compiler flags per compiler and build type (gfortran is the supported compiler).
if(CMAKE_Fortran_COMPILER_ID STREQUAL "GNU")
  set(ICTUS_FFLAGS_COMMON -ffree-line-length-132 -fimplicit-none -std=f2018 -Wall
      -Wno-maybe-uninitialized)
  set(CMAKE_Fortran_FLAGS_RELEASE "-O3 -funroll-loops -g")
  set(CMAKE_Fortran_FLAGS_DEBUG
      "-O0 -g -fbacktrace -fcheck=all -ffpe-trap=invalid,zero,overflow -finit-real=snan -finit-integer=-99999999 -finit-derived")
  if(ICTUS_NATIVE)
    string(APPEND CMAKE_Fortran_FLAGS_RELEASE " -march=native")
  endif()
  if(ICTUS_DETERMINISTIC)
    list(APPEND ICTUS_FFLAGS_COMMON -ffp-contract=off)
  endif()
else()
  message(WARNING "ictus is tested with gfortran only; using the compiler's default flags")
  set(ICTUS_FFLAGS_COMMON "")
endif()
