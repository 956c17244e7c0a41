# tripsitter_verilate, for rtl/ and for fuzz/ (the receiver_pins fuzzer Verilates the receiver top alone, without
# the rest of rtl/). Needs find_package(verilator) first: it uses its verilate() and VERILATOR_ROOT.
include_guard(GLOBAL)

# tripsitter_verilate(MODEL IN LIBRARY TOP module SOURCES file.sv... [PARAMS NAME=VALUE...] [DEFINES NAME[=VALUE]...]
# [TRACE]): adds the Verilated model of `module` to the static library LIBRARY (made on first use) as the C++ class
# V<MODEL> (header V<MODEL>.h), with its top parameters overridden by PARAMS and the macros DEFINES set. The models
# of a block share one library, so Verilator's runtime is compiled once per block, not once per model. The
# SystemVerilog is linted with -Wall: a Verilator warning fails the build. TRACE adds VCD tracing (VerilatedVcdC).
# The generated C++ is Verilator's, not ours, so the project's warnings are not applied to it; all of it, and
# Verilator's runtime, is compiled with TRIPSITTER_RTL_OPT, each model as one file (a unity group): the models'
# compile took 565 s of CPU as 293 files at -O1, 258 s as one file a model.
set(TRIPSITTER_RTL_OPT -O1 CACHE STRING
    "Optimisation of the Verilated models. -O1: the wide top (one file) compiles in 73 s against 204 s at -O2, and its test simulates within 3% as fast (docs/rtl.md)")
function(tripsitter_verilate model)
  cmake_parse_arguments(ARG "TRACE" "IN;TOP" "SOURCES;PARAMS;DEFINES" ${ARGN})
  if(NOT TARGET ${ARG_IN})
    add_library(${ARG_IN} STATIC)
    target_compile_options(${ARG_IN} PRIVATE -w ${TRIPSITTER_RTL_OPT})
    set_target_properties(${ARG_IN} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
    # Verilator's runtime headers are not warning-clean under the project's flags: users see them as system headers.
    target_include_directories(${ARG_IN} SYSTEM INTERFACE ${VERILATOR_ROOT}/include ${VERILATOR_ROOT}/include/vltstd)
  endif()
  set(args -Wall --x-assign unique --x-initial unique -O3)
  foreach(p IN LISTS ARG_PARAMS)
    list(APPEND args -G${p})
  endforeach()
  foreach(d IN LISTS ARG_DEFINES)
    list(APPEND args +define+${d})
  endforeach()
  set(trace)
  if(ARG_TRACE)
    set(trace TRACE)
  endif()
  get_target_property(before ${ARG_IN} SOURCES)
  verilate(${ARG_IN} SOURCES ${ARG_SOURCES} TOP_MODULE ${ARG_TOP} PREFIX V${model} VERILATOR_ARGS ${args} ${trace})
  # The model's generated files are compiled as one (a unity group): most of a small model's compile was
  # Verilator's headers, parsed once per file. Verilator's runtime (added on the library's first model) stays apart.
  get_target_property(after ${ARG_IN} SOURCES)
  if(before)
    list(REMOVE_ITEM after ${before})
  endif()
  foreach(source IN LISTS after)
    if(source MATCHES "/V${model}\\.dir/[^/]*\\.cpp$")
      set_source_files_properties(${source} TARGET_DIRECTORY ${ARG_IN} PROPERTIES UNITY_GROUP ${model})
    endif()
  endforeach()
endfunction()
