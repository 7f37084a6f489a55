# cmake -DINPUT=<file> -DOUTPUT=<header> -DNAME=<identifier> -P embed_template.cmake
# Writes a header that holds the text of INPUT, unchanged, as `inline constexpr char NAME[]` (a raw
# string literal), so that report.html carries its style sheet and script in the page itself.
file(READ "${INPUT}" text)
set(delimiter "embedded")  # at most 16 characters (C++ raw string literals)
string(FIND "${text}" ")${delimiter}\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains )${delimiter}\", which would end the raw string literal")
endif()
get_filename_component(source_name "${INPUT}" NAME)
file(WRITE "${OUTPUT}.partial"
  "// Generated from reports/templates/${source_name} by reports/templates/embed_template.cmake: edit that file.\n"
  "#pragma once\n\n"
  "namespace causticbench::report_detail {\n\n"
  "inline constexpr char ${NAME}[] = R\"${delimiter}(${text})${delimiter}\";\n\n"
  "}  // namespace causticbench::report_detail\n")
file(RENAME "${OUTPUT}.partial" "${OUTPUT}")
