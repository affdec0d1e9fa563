# The CMake functions of the chainsim package (docs/firmware.md, "Your own
# program"). The shipped programs are built with chainsim_add_firmware too
# (firmware/CMakeLists.txt), so a program of your own gets the same language
# level and warnings.
#
#   chainsim_add_firmware(<name> <source.c>... [PIC_SERVOS <n>] [PIC_DEFINES <-DX=Y>...])
#       an executable <name> linked with hal-sim and the firmware common
#       library: C99, no extensions, -Wall -Wextra. With the option
#       CHAINSIM_PIC=ON the same sources are also cross-built for the
#       PIC18F2550: target <name>-pic makes <name>.hex (+ .cod, .map, .size,
#       .pic.json) beside the executable, where chainsim finds it for a
#       module whose target is pic, with the SDCC toolchain cached by
#       pic-toolchain.sh; it fails when the program is over the part's flash
#       or RAM, and says why when a variable does not fit a RAM bank.
#       PIC_SERVOS: the board's servo outputs (default 2: the module type's
#       servos). With CHAINSIM_PIC_STRICT=ON, SDCC's warnings that mean the
#       board computes something else than a PC (integer overflow, a shift
#       wider than int, ...) are errors (docs/pic-in-the-loop.md).
#
#   chainsim_add_test(NAME <test> TESTS <file.test.yaml or folder>... [TARGET native|pic] [ARGS <more chainsim test options>...])
#       a ctest that runs `chainsim test` on the files, finding the programs
#       of chainsim_add_firmware first (--firmware-dir), and writes a JUnit
#       report <build folder>/<test>.junit.xml. TARGET pic runs every
#       module on its .hex in gpsim (--target pic; needs CHAINSIM_PIC=ON).
include_guard(GLOBAL)

option(CHAINSIM_PIC "also cross-build every chainsim_add_firmware program for the PIC18F2550 (.hex)" OFF)
option(CHAINSIM_PIC_STRICT "the PIC build fails on SDCC's warnings that mean the board computes something else" OFF)

# the shipped programs' language level and warnings
set(CHAINSIM_FIRMWARE_C_OPTIONS -Wall -Wextra)

function(chainsim_add_firmware name)
  cmake_parse_arguments(PARSE_ARGV 1 F "" "PIC_SERVOS" "PIC_DEFINES")
  set(sources ${F_UNPARSED_ARGUMENTS})
  if(NOT sources)
    message(FATAL_ERROR "chainsim_add_firmware(${name}): no source files")
  endif()
  add_executable(${name} ${sources})
  target_link_libraries(${name} PRIVATE chainsim::fw_common chainsim::hal_sim)
  # NO_SYSTEM_FROM_IMPORTED: chainsim's headers warn as they do for the shipped programs
  set_target_properties(${name} PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF
                                           NO_SYSTEM_FROM_IMPORTED ON)
  target_compile_options(${name} PRIVATE ${CHAINSIM_FIRMWARE_C_OPTIONS})
  set_property(GLOBAL APPEND PROPERTY CHAINSIM_FIRMWARE_TARGETS ${name})

  if(CHAINSIM_PIC)
    if(NOT DEFINED F_PIC_SERVOS)
      set(F_PIC_SERVOS 2)
    endif()
    if(NOT CHAINSIM_PIC_CACHE)
      if(DEFINED ENV{CHAINSIM_PIC_CACHE})
        set(CHAINSIM_PIC_CACHE "$ENV{CHAINSIM_PIC_CACHE}")
      else()
        set(CHAINSIM_PIC_CACHE "$ENV{HOME}/.cache/chainsim-pic")
      endif()
    endif()
    set(srcs "")
    foreach(s ${sources})
      get_filename_component(s "${s}" ABSOLUTE)
      list(APPEND srcs "${s}")
    endforeach()
    include("${CHAINSIM_PIC_CMAKE}")
    # beside the executable: found by --firmware-dir as the native program is
    set(out_dir "${CMAKE_CURRENT_BINARY_DIR}")
    if(CMAKE_RUNTIME_OUTPUT_DIRECTORY)
      set(out_dir "${CMAKE_RUNTIME_OUTPUT_DIRECTORY}")
    endif()
    set(strict "")
    if(CHAINSIM_PIC_STRICT)
      set(strict STRICT)
    endif()
    chainsim_pic_program(TARGET ${name}-pic OUTPUT "${out_dir}/${name}" ${strict}
                         SOURCES ${srcs} SERVOS ${F_PIC_SERVOS} DEFINES ${F_PIC_DEFINES}
                         INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
endfunction()

function(chainsim_add_test)
  cmake_parse_arguments(PARSE_ARGV 0 T "" "NAME;TARGET" "TESTS;ARGS")
  if(NOT T_NAME OR NOT T_TESTS)
    message(FATAL_ERROR "chainsim_add_test: NAME and TESTS are required")
  endif()
  set(target_args "")
  if(T_TARGET)
    if(NOT T_TARGET MATCHES "^(native|pic)$")
      message(FATAL_ERROR "chainsim_add_test(${T_NAME}): TARGET ${T_TARGET}: native or pic")
    endif()
    if(T_TARGET STREQUAL "pic" AND NOT CHAINSIM_PIC)
      message(FATAL_ERROR "chainsim_add_test(${T_NAME}): TARGET pic runs the programs' .hex: configure with "
                          "-DCHAINSIM_PIC=ON")
    endif()
    set(target_args --target ${T_TARGET})
  endif()
  set(tests "")
  foreach(t ${T_TESTS})
    get_filename_component(t "${t}" ABSOLUTE)
    list(APPEND tests "${t}")
  endforeach()
  # the folders of this project's programs, searched before chainsim's own
  get_property(programs GLOBAL PROPERTY CHAINSIM_FIRMWARE_TARGETS)
  set(dirs "")
  foreach(p ${programs})
    list(APPEND dirs "$<TARGET_FILE_DIR:${p}>")
  endforeach()
  list(REMOVE_DUPLICATES dirs)
  string(JOIN ":" firmware_dirs ${dirs})
  set(fw_args "")
  if(firmware_dirs)
    set(fw_args --firmware-dir "${firmware_dirs}")
  endif()
  add_test(NAME ${T_NAME}
           COMMAND chainsim::chainsim test ${tests} ${fw_args} ${target_args}
                   --junit "${CMAKE_CURRENT_BINARY_DIR}/${T_NAME}.junit.xml"
                   --keep "${CMAKE_CURRENT_BINARY_DIR}/${T_NAME}-runs" ${T_ARGS}
           WORKING_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}")
endfunction()
