// JSON text of a document whose strings may hold any bytes: a file, material or folder name read
// from disk need not be UTF-8 (a Latin-1 "café.obj"), and nlohmann's dump() throws type_error 316
// on it (before stop 44, after a whole build: "hlod build: [json.exception.type_error.316] …").
// Bytes that are not UTF-8 are written as U+FFFD; everything else as dump() writes it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace hlod {

inline std::string jsonText(const nlohmann::json& j, int indent = -1) {
    return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace hlod
