# Turns the page's files into a C++ source, so fleet-server serves the page it was built with.
# cmake -DOUT=<file.cpp> -DBASE=<dir> -DFILES="index.html;app.js;..." -P embed_assets.cmake
set(code "// Generated from server/web/ by server/web/embed_assets.cmake; edit those files instead.\n")
string(APPEND code "#include <cstddef>\n\nnamespace fleet::server::web_assets {\n")
string(APPEND code "struct Entry {\n  const char* path;\n  const unsigned char* data;\n  std::size_t size;\n};\n")
set(entries "")
set(index 0)
foreach(name IN LISTS FILES)
  file(READ "${BASE}/${name}" hex HEX)
  string(LENGTH "${hex}" hex_length)
  math(EXPR size "${hex_length} / 2")
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
  # Break the byte list into lines of 32 bytes to keep the source readable by compilers and people.
  string(REGEX REPLACE "((0x[0-9a-f][0-9a-f],){32})" "\\1\n" bytes "${bytes}")
  string(APPEND code "static const unsigned char asset_${index}[] = {\n${bytes}\n};\n")
  string(APPEND entries "    {\"${name}\", asset_${index}, ${size}},\n")
  math(EXPR index "${index} + 1")
endforeach()
string(APPEND code "extern const Entry kEntries[] = {\n${entries}};\n")
string(APPEND code "extern const std::size_t kEntryCount = ${index};\n}  // namespace fleet::server::web_assets\n")
file(WRITE "${OUT}.tmp" "${code}")
# Only touch the output when it changed, so an unchanged page does not relink the server.
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
