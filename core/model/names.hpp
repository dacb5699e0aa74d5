#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fleet::model {

/// "a, b, c" for messages that list valid values.
std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");

/// Up to `limit` of `candidates` closest to `name` by edit distance, best first; used when an
/// unknown name has many possible meanings.
std::vector<std::string> closest_names(const std::string& name, const std::vector<std::string>& candidates,
                                       std::size_t limit = 5);

/// `text` as a message quotes it: whole up to `longest` characters, else its start and its length.
std::string excerpt(const std::string& text, std::size_t longest = 60);

/// "unknown loading area 'NOPE'; valid: A1, A2" (or "closest: ..." when there are many). A name
/// longer than any name can be is quoted by its start, with no search for the closest.
std::string unknown_name_message(const std::string& what, const std::string& name,
                                 const std::vector<std::string>& valid);

/// Order ids as text, space-separated ("12 14 15"), as the order database and the wire carry
/// them, and back; nullopt for anything but ids.
std::string ids_text(const std::vector<std::int64_t>& ids);
std::optional<std::vector<std::int64_t>> parse_ids(std::string_view text);

}  // namespace fleet::model
