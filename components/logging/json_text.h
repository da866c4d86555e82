#pragma once
// JSON text for the files dmpl writes itself (column metadata, the hand's geometry): small enough
// not to need a JSON library.
#include <string>
#include <vector>

namespace dmpl {

// A JSON string literal: quotes and backslashes escaped, bytes outside printable ASCII as \uXXXX.
std::string JsonString(const std::string& s);
// A JSON list of strings.
std::string JsonList(const std::vector<std::string>& items);

}  // namespace dmpl
