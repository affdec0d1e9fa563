# chainsim_pic_program(): one module program cross-built for the PIC18F2550
# with SDCC's pic16 port and gputils, linked with hal-pic and the firmware
# common library. Used by hal-pic/CMakeLists.txt (the shipped programs,
# tools/pic-build.sh) and by the chainsim CMake package (chainsim_add_firmware
# with CHAINSIM_PIC=ON, a user's own program).
#
#   chainsim_pic_program(TARGET <target> OUTPUT <dir/name>   # -> <dir/name>.hex, .cod, .map, .size, .pic.json
#                        SOURCES <file.c>...                 # the program; one of them defines main()
#                        [SERVOS <n>]                        # servo outputs, 0..4 (default 2)
#                        [STRICT]                            # SDCC's 8-bit truths are errors (tools/pic-cc.py)
#                        [DEFINES <-DX=Y>...] [INCLUDE_DIRS <dir>...])
#
# gplink runs through tools/pic-link.py, which tells a RAM section that does
# not fit a bank in words (the variables in it, their sizes).
# gplink fails (naming the section) when the program does not fit at all; the
# size check runs on every build (it is the build's report) and fails it,
# removing the .hex, when the program is over the part's flash or RAM. The
# .pic.json beside it is what the simulator's PIC module process needs of the
# build: flash, RAM and stack use and the servo outputs (tools/pic-size.py).
#
# Needs (set by the caller): CHAINSIM_PIC_CACHE (tools/pic-toolchain.sh's
# cache), CHAINSIM_HAL_INCLUDE_DIR (hal/), CHAINSIM_FW_COMMON_INCLUDE_DIR and
# CHAINSIM_FW_COMMON_SOURCES (firmware/common), CHAINSIM_PIC_HAL_DIR (hal-pic/
# sources) and CHAINSIM_PIC_TOOLS_DIR (where pic-toolchain.sh, pic-size.py,
# pic-cc.py and pic-link.py are: tools/, or the installed share/chainsim/pic).
include_guard(GLOBAL)

# the part and the toolchain's files (a missing one names the script that
# makes it); a macro, so that its variables land in the calling function,
# whatever scope this file was first included from
macro(_chainsim_pic_toolchain)
  set(CHAINSIM_PIC_TOOLCHAIN_SCRIPT "${CHAINSIM_PIC_TOOLS_DIR}/pic-toolchain.sh")
  set(CHAINSIM_PIC_SIZE_SCRIPT "${CHAINSIM_PIC_TOOLS_DIR}/pic-size.py")
  set(CHAINSIM_PIC_CC_SCRIPT "${CHAINSIM_PIC_TOOLS_DIR}/pic-cc.py")
  set(CHAINSIM_PIC_LINK_SCRIPT "${CHAINSIM_PIC_TOOLS_DIR}/pic-link.py")
  set(CHAINSIM_PIC_DEVICE 18f2550)
  set(CHAINSIM_PIC_FLASH_BYTES 32768)
  set(CHAINSIM_PIC_RAM_BYTES 2048)
  set(CHAINSIM_PIC_SDCC "${CHAINSIM_PIC_CACHE}/sdcc/bin/sdcc")
  set(CHAINSIM_PIC_RT "${CHAINSIM_PIC_CACHE}/rt")
  set(CHAINSIM_PIC_LKR "/usr/share/gputils/lkr/${CHAINSIM_PIC_DEVICE}_g.lkr")
  foreach(f "${CHAINSIM_PIC_SDCC}" "${CHAINSIM_PIC_RT}/crt0i.o" "${CHAINSIM_PIC_RT}/stack.o"
          "${CHAINSIM_PIC_RT}/pic${CHAINSIM_PIC_DEVICE}.o" "${CHAINSIM_PIC_RT}/libsdcc.lib" "${CHAINSIM_PIC_LKR}")
    if(NOT EXISTS "${f}")
      message(FATAL_ERROR "${f} is missing: build the PIC toolchain first with ${CHAINSIM_PIC_TOOLCHAIN_SCRIPT} "
                          "(CHAINSIM_PIC_CACHE=${CHAINSIM_PIC_CACHE})")
    endif()
  endforeach()
  find_program(CHAINSIM_GPLINK gplink REQUIRED)
  find_program(CHAINSIM_GPLIB gplib REQUIRED)
  find_package(Python3 REQUIRED COMPONENTS Interpreter)
endmacro()

function(chainsim_pic_program)
  cmake_parse_arguments(PARSE_ARGV 0 P "STRICT" "TARGET;OUTPUT;SERVOS" "SOURCES;DEFINES;INCLUDE_DIRS")
  if(NOT P_TARGET OR NOT P_OUTPUT OR NOT P_SOURCES)
    message(FATAL_ERROR "chainsim_pic_program: TARGET, OUTPUT and SOURCES are required")
  endif()
  if(NOT DEFINED P_SERVOS)
    set(P_SERVOS 2)
  endif()
  _chainsim_pic_toolchain()
  set(rt "${CHAINSIM_PIC_RT}")
  set(python "${Python3_EXECUTABLE}")
  set(sdcc "${CHAINSIM_PIC_SDCC}")
  if(P_STRICT)
    set(sdcc "${python}" "${CHAINSIM_PIC_CC_SCRIPT}" -- "${CHAINSIM_PIC_SDCC}")
  endif()

  # the same flags as SDCC's own pic16 library build; -Wa,-q keeps gpasm quiet
  set(cflags -mpic16 -p${CHAINSIM_PIC_DEVICE} --std-c99 --no-warn-non-free
      --fomit-frame-pointer --obanksel=9 --denable-peeps --optimize-cmp --optimize-df -Wa,-q)
  foreach(d ${P_INCLUDE_DIRS} ${CHAINSIM_HAL_INCLUDE_DIR} ${CHAINSIM_FW_COMMON_INCLUDE_DIR} ${CHAINSIM_PIC_HAL_DIR})
    list(APPEND cflags "-I${d}")
  endforeach()
  # HAL_PARAM_NO_TEXT: parameter tables without the simulator's type and meaning (hal/hal_param.h)
  list(APPEND cflags -DHAL_PIC_SERVOS=${P_SERVOS} -DHAL_PARAM_NO_TEXT ${P_DEFINES})
  file(GLOB hal_sources CONFIGURE_DEPENDS "${CHAINSIM_PIC_HAL_DIR}/hal_*.c")
  file(GLOB headers CONFIGURE_DEPENDS "${CHAINSIM_HAL_INCLUDE_DIR}/*.h" "${CHAINSIM_FW_COMMON_INCLUDE_DIR}/*.h"
       "${CHAINSIM_PIC_HAL_DIR}/*.h")

  # the configuration words go with main() (SDCC checks XINST there), and only there
  set(main_c "")
  set(app_sources "")
  foreach(src ${P_SOURCES})
    get_filename_component(src "${src}" ABSOLUTE)
    list(APPEND app_sources "${src}")
    get_filename_component(src_dir "${src}" DIRECTORY)
    file(GLOB app_headers CONFIGURE_DEPENDS "${src_dir}/*.h")  # the program's own headers
    list(APPEND headers ${app_headers})
    file(STRINGS "${src}" mains REGEX "^[ \t]*(int|void)[ \t]+main[ \t]*\\(")
    if(mains)
      if(main_c)
        message(FATAL_ERROR "chainsim_pic_program(${P_TARGET}): main() in both ${main_c} and ${src}")
      endif()
      set(main_c "${src}")
    endif()
  endforeach()
  if(NOT main_c)
    message(FATAL_ERROR "chainsim_pic_program(${P_TARGET}): none of the SOURCES defines main()")
  endif()

  get_filename_component(name "${P_OUTPUT}" NAME)
  set(objdir "${CMAKE_CURRENT_BINARY_DIR}/pic-obj/${name}")
  set(objs "")
  set(common_objs "")
  set(seen "")
  foreach(src ${app_sources} ${CHAINSIM_FW_COMMON_SOURCES} ${hal_sources})
    get_filename_component(base "${src}" NAME_WE)
    if(src STREQUAL main_c)
      set(extra "-Wp-include,${CHAINSIM_PIC_HAL_DIR}/hal_pic_config.h")
      set(base "main_${name}")
    else()
      set(extra "")
    endif()
    if(base IN_LIST seen)
      message(FATAL_ERROR "chainsim_pic_program(${P_TARGET}): two sources named ${base}.c "
                          "(the firmware common library and hal-pic have: ${CHAINSIM_FW_COMMON_SOURCES} ${hal_sources})")
    endif()
    list(APPEND seen "${base}")
    set(obj "${objdir}/${base}.o")
    add_custom_command(
      OUTPUT "${obj}"
      COMMAND "${CMAKE_COMMAND}" -E make_directory "${objdir}"
      COMMAND ${sdcc} ${cflags} ${extra} -c "${src}" -o "${obj}"
      DEPENDS "${src}" ${headers}
      COMMENT "SDCC ${name}: ${base}.c"
      VERBATIM)
    if(src IN_LIST CHAINSIM_FW_COMMON_SOURCES)
      list(APPEND common_objs "${obj}")
    else()
      list(APPEND objs "${obj}")
    endif()
  endforeach()

  # firmware/common as a library: gplink takes from it only the objects
  # whose symbols the program uses (an object file it is given, it keeps
  # whole), so a program does not carry the gaits or the module loop it
  # never calls
  set(commonlib "${objdir}/fw-common.lib")
  add_custom_command(
    OUTPUT "${commonlib}"
    COMMAND "${CMAKE_COMMAND}" -E rm -f "${commonlib}"
    COMMAND "${CHAINSIM_GPLIB}" -c "${commonlib}" ${common_objs}
    DEPENDS ${common_objs}
    COMMENT "gplib ${name}: firmware/common"
    VERBATIM)

  set(out "${P_OUTPUT}")
  set(rtobjs "${rt}/crt0i.o" "${rt}/stack.o")
  add_custom_command(
    OUTPUT "${out}.hex" "${out}.cod" "${out}.map"
    COMMAND "${python}" "${CHAINSIM_PIC_LINK_SCRIPT}" --asm-dir "${objdir}" --
            "${CHAINSIM_GPLINK}" -w -r -s "${CHAINSIM_PIC_LKR}" -m -o "${out}.hex"
            ${rtobjs} ${objs} "${commonlib}" "${rt}/pic${CHAINSIM_PIC_DEVICE}.o" "${rt}/libsdcc.lib"
    DEPENDS ${objs} "${commonlib}" ${rtobjs} "${rt}/pic${CHAINSIM_PIC_DEVICE}.o" "${rt}/libsdcc.lib"
    COMMENT "gplink ${name}.hex"
    VERBATIM)
  add_custom_target(${P_TARGET} ALL
    COMMAND "${python}" "${CHAINSIM_PIC_SIZE_SCRIPT}" "${out}.map" --name "${name}.hex"
            --flash ${CHAINSIM_PIC_FLASH_BYTES} --ram ${CHAINSIM_PIC_RAM_BYTES}
            --report "${out}.size" --json "${out}.pic.json" --servos ${P_SERVOS}
            --remove-on-fail "${out}.hex"
    DEPENDS "${out}.hex"
    VERBATIM)
endfunction()
