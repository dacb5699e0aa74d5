#pragma once

#include <string>
#include <vector>

namespace fleet::model {

/// "a, b, c" for messages that list valid values.
std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");

/// Up to `limit` of `candidates` closest to `name` by edit distance, best first; used when an
/// unknown name has many possible meanings.
std::vector<std::string> closest_names(const std::string& name, const std::vector<std::string>& candidates,
                                       std::size_t limit = 5);

/// "unknown loading area 'NOPE'; valid: A1, A2" (or "closest: ..." when there are many).
std::string unknown_name_message(const std::string& what, const std::string& name,
                                 const std::vector<std::string>& valid);

}  // namespace fleet::model
