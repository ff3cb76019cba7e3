# Writes OUT, a C++ source defining `extern const char rt::<NAME>[]` as the text of IN (a raw string
# literal), so the viewer's script is edited as a .js file and compiled into the library.
file(READ "${IN}" content)
string(FIND "${content}" ")rt_embed\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter )rt_embed\"")
endif()
file(WRITE "${OUT}.tmp" "// Generated from ${IN} by embed_text.cmake; do not edit.\nnamespace rt {\nextern const char ${NAME}[];\nconst char ${NAME}[] = R\"rt_embed(${content})rt_embed\";\n}  // namespace rt\n")
file(RENAME "${OUT}.tmp" "${OUT}")
