// JSON text of a document whose strings may hold any bytes: a file, material or folder name read
// from disk need not be UTF-8 (a Latin-1 "café.obj"), and nlohmann's dump() throws type_error 316
// on it (before stop 44, after a whole build: "hlod build: [json.exception.type_error.316] …").
// Bytes that are not UTF-8 are written as U+FFFD; everything else as dump() writes it.
// jsonProblem: nlohmann's error texts without their tag.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace hlod {

inline std::string jsonText(const nlohmann::json& j, int indent = -1) {
    return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// An error text without nlohmann's tag ("[json.exception.out_of_range.403] key 'x' not found" is
// "key 'x' not found"): the sentence a one-line error quotes (the tag was shown until stop 46).
inline std::string jsonProblem(const std::string& what) {
    const size_t at = what.find("[json.exception.");
    if (at == std::string::npos) return what;
    const size_t end = what.find("] ", at);
    return what.substr(0, at) + (end == std::string::npos ? std::string() : what.substr(end + 2));
}

}  // namespace hlod
