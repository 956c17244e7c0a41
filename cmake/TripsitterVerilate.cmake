# tripsitter_verilate, for rtl/ and for fuzz/ (the receiver_pins fuzzer Verilates the receiver top alone, without
# the rest of rtl/). Needs find_package(verilator) first: it uses its verilate() and VERILATOR_ROOT.
include_guard(GLOBAL)

# tripsitter_verilate(MODEL IN LIBRARY TOP module SOURCES file.sv... [PARAMS NAME=VALUE...] [DEFINES NAME[=VALUE]...]
# [TRACE]): adds the Verilated model of `module` to the static library LIBRARY (made on first use) as the C++ class
# V<MODEL> (header V<MODEL>.h), with its top parameters overridden by PARAMS and the macros DEFINES set. The models
# of a block share one library, and every library links Verilator's runtime, compiled once (tripsitter_verilated,
# below). The SystemVerilog is linted with -Wall: a Verilator warning fails the build. TRACE adds VCD tracing
# (VerilatedVcdC). The generated C++ is Verilator's, not ours, so the project's warnings are not applied to it; all of
# it, and Verilator's runtime, is compiled with TRIPSITTER_RTL_OPT, each model as one file (a unity group): the
# models' compile took 565 s of CPU as 293 files at -O1, 258 s as one file a model.
set(TRIPSITTER_RTL_OPT -O1 CACHE STRING
    "Optimisation of the Verilated models. -O1: the wide top (one file) compiles in 73 s against 204 s at -O2, and its test simulates within 3% as fast (docs/rtl.md)")

# Verilator's runtime (its "global" sources: verilated.cpp, verilated_threads.cpp, and verilated_vcd_c.cpp once a
# model is traced), compiled once into tripsitter_verilated, which every model library links. verilate() adds it to
# each library it Verilates into, where it was compiled once a library (eight times in the release build); none of
# it depends on a library's VM_* switches.
function(tripsitter_verilated_runtime)
  if(TARGET tripsitter_verilated)
    return()
  endif()
  add_library(tripsitter_verilated STATIC ${VERILATOR_ROOT}/include/verilated.cpp
              ${VERILATOR_ROOT}/include/verilated_threads.cpp)
  target_compile_options(tripsitter_verilated PRIVATE -w ${TRIPSITTER_RTL_OPT})
  target_compile_definitions(tripsitter_verilated PRIVATE VM_COVERAGE=0 VM_SC=0 VM_TRACE=1 VM_TRACE_VCD=1
                             VM_TRACE_FST=0)
  target_compile_features(tripsitter_verilated PRIVATE cxx_std_11)
  # Verilator's runtime headers are not warning-clean under the project's flags: users see them as system headers.
  target_include_directories(tripsitter_verilated SYSTEM PUBLIC ${VERILATOR_ROOT}/include
                             ${VERILATOR_ROOT}/include/vltstd)
  find_package(Threads REQUIRED)
  target_link_libraries(tripsitter_verilated PUBLIC Threads::Threads)
endfunction()

function(tripsitter_verilate model)
  cmake_parse_arguments(ARG "TRACE" "IN;TOP" "SOURCES;PARAMS;DEFINES" ${ARGN})
  if(NOT TARGET ${ARG_IN})
    tripsitter_verilated_runtime()
    add_library(${ARG_IN} STATIC)
    target_compile_options(${ARG_IN} PRIVATE -w ${TRIPSITTER_RTL_OPT})
    set_target_properties(${ARG_IN} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
    target_link_libraries(${ARG_IN} PUBLIC tripsitter_verilated)
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
    get_target_property(runtime tripsitter_verilated SOURCES)
    if(NOT "${VERILATOR_ROOT}/include/verilated_vcd_c.cpp" IN_LIST runtime)
      target_sources(tripsitter_verilated PRIVATE ${VERILATOR_ROOT}/include/verilated_vcd_c.cpp)
    endif()
  endif()
  get_target_property(before ${ARG_IN} SOURCES)
  verilate(${ARG_IN} SOURCES ${ARG_SOURCES} TOP_MODULE ${ARG_TOP} PREFIX V${model} VERILATOR_ARGS ${args} ${trace})
  # The model's generated files are compiled as one (a unity group): most of a small model's compile was
  # Verilator's headers, parsed once per file.
  get_target_property(after ${ARG_IN} SOURCES)
  # Verilator's runtime is tripsitter_verilated's.
  list(FILTER after EXCLUDE REGEX "^${VERILATOR_ROOT}/include/")
  set_property(TARGET ${ARG_IN} PROPERTY SOURCES ${after})
  if(before)
    list(REMOVE_ITEM after ${before})
  endif()
  foreach(source IN LISTS after)
    if(source MATCHES "/V${model}\\.dir/[^/]*\\.cpp$")
      set_source_files_properties(${source} TARGET_DIRECTORY ${ARG_IN} PROPERTIES UNITY_GROUP ${model})
    endif()
  endforeach()
endfunction()
