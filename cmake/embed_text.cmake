# cmake -DIN=FILE -DOUT=FILE.cpp -DNAMESPACE=ns -DFUNCTION=name -P embed_text.cmake
# Writes a C++ source whose function NAMESPACE::FUNCTION() returns the text of IN as a
# std::string_view (a raw string literal; the text must not contain the delimiter).
file(READ "${IN}" content)
string(FIND "${content}" ")pxembed\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter )pxembed\"")
endif()
file(WRITE "${OUT}.tmp" "// Generated from ${IN} by cmake/embed_text.cmake. Do not edit.\n#include <string_view>\n\nnamespace ${NAMESPACE} {\n\nstd::string_view ${FUNCTION}() {\n  static const char kText[] = R\"pxembed(")
file(APPEND "${OUT}.tmp" "${content}")
file(APPEND "${OUT}.tmp" ")pxembed\";\n  return {kText, sizeof(kText) - 1};\n}\n\n}  // namespace ${NAMESPACE}\n")
file(RENAME "${OUT}.tmp" "${OUT}")
