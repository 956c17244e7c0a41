# Embeds text files into C++ at build time, so a program carries them instead of reading them at run time:
#
#   cmake -DOUTPUT=<file.cpp> -DNAMESPACE=<a::b> -P embed_text.cmake -- <function> <file> [<function> <file>...]
#
# writes OUTPUT with one function per file, `std::string <function>();` in NAMESPACE, returning the file's bytes
# exactly. Each file becomes raw string literals of at most kChunk bytes (compilers limit a literal's length;
# MSVC's is 16 KB), joined at run time, under a delimiter the script checks the text does not contain. Text only:
# a file with a NUL byte, or one that cannot be read whole, stops the build.

cmake_minimum_required(VERSION 3.25)  # the project's; sets the policies of a -P script

set(kChunk 15000)

if(NOT OUTPUT OR NOT NAMESPACE)
  message(FATAL_ERROR "embed_text.cmake: set -DOUTPUT=<file.cpp> and -DNAMESPACE=<namespace>")
endif()

# The arguments after "--": pairs of function name and file.
set(pairs "")
set(after_dashes FALSE)
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE 0 ${last})
  if(after_dashes)
    list(APPEND pairs "${CMAKE_ARGV${i}}")
  elseif(CMAKE_ARGV${i} STREQUAL "--")
    set(after_dashes TRUE)
  endif()
endforeach()
list(LENGTH pairs count)
math(EXPR odd "${count} % 2")
if(count EQUAL 0 OR odd)
  message(FATAL_ERROR "embed_text.cmake: after -- give pairs of <function> <file>, got: ${pairs}")
endif()

set(sources "")
set(body "")
math(EXPR last_pair "${count} / 2 - 1")
foreach(p RANGE 0 ${last_pair})
  math(EXPR name_at "2 * ${p}")
  math(EXPR file_at "2 * ${p} + 1")
  list(GET pairs ${name_at} name)
  list(GET pairs ${file_at} file)
  if(NOT name MATCHES "^[A-Za-z_][A-Za-z0-9_]*$")
    message(FATAL_ERROR "embed_text.cmake: '${name}' is not a C++ identifier")
  endif()
  if(NOT EXISTS "${file}")
    message(FATAL_ERROR "embed_text.cmake: cannot read '${file}'")
  endif()

  file(READ "${file}" text)
  file(SIZE "${file}" size)
  string(LENGTH "${text}" length)
  if(NOT length EQUAL size)
    message(FATAL_ERROR "embed_text.cmake: '${file}' read ${length} of its ${size} bytes (a NUL byte?): text only")
  endif()

  # The first delimiter whose closing sequence )DELIM" the text does not contain.
  set(delimiter "")
  foreach(candidate TSEMBED TSEMBED1 TSEMBED2 TSEMBED3 TSEMBED4 TSEMBED5 TSEMBED6 TSEMBED7 TSEMBED8 TSEMBED9)
    string(FIND "${text}" ")${candidate}\"" at)
    if(at EQUAL -1)
      set(delimiter ${candidate})
      break()
    endif()
  endforeach()
  if(delimiter STREQUAL "")
    message(FATAL_ERROR "embed_text.cmake: '${file}' contains every candidate raw-string delimiter")
  endif()

  set(chunks "")
  set(n 0)
  set(begin 0)
  while(begin LESS length)
    string(SUBSTRING "${text}" ${begin} ${kChunk} chunk)
    string(APPEND chunks "    R\"${delimiter}(${chunk})${delimiter}\",\n")
    math(EXPR begin "${begin} + ${kChunk}")
    math(EXPR n "${n} + 1")
  endwhile()
  if(n EQUAL 0)
    string(APPEND chunks "    \"\",\n")
  endif()

  string(APPEND sources "//   ${name}: ${file}\n")
  string(APPEND body "// ${name}: ${length} bytes in ${n} literals.\n"
                     "std::string ${name}() {\n"
                     "  static const char* const kChunks[] = {\n${chunks}  };\n"
                     "  return join(kChunks, sizeof kChunks / sizeof kChunks[0], ${length});\n"
                     "}\n\n")
endforeach()

string(CONCAT out "// Generated at build time by cmake/embed_text.cmake from the files below: do not edit it, edit them.\n"
               "${sources}"
               "#include <cstddef>\n"
               "#include <string>\n\n"
               "namespace ${NAMESPACE} {\n"
               "namespace {\n\n"
               "std::string join(const char* const* chunks, std::size_t n, std::size_t size) {\n"
               "  std::string text;\n"
               "  text.reserve(size);\n"
               "  for (std::size_t i = 0; i < n; ++i) text += chunks[i];\n"
               "  return text;\n"
               "}\n\n"
               "}  // namespace\n\n"
               "${body}"
               "}  // namespace ${NAMESPACE}\n")
file(WRITE "${OUTPUT}" "${out}")
