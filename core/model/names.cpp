#include "model/names.hpp"

#include <algorithm>
#include <charconv>
#include <numeric>

namespace fleet::model {

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? separator : "") + items[i];
  return out;
}

namespace {
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), 0);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const bool same = std::tolower(a[i - 1]) == std::tolower(b[j - 1]);
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}
}  // namespace

std::vector<std::string> closest_names(const std::string& name, const std::vector<std::string>& candidates,
                                       std::size_t limit) {
  std::vector<std::pair<std::size_t, std::string>> scored;
  for (const auto& c : candidates) scored.emplace_back(edit_distance(name, c), c);
  std::stable_sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < scored.size() && i < limit; ++i) out.push_back(scored[i].second);
  return out;
}

std::string excerpt(const std::string& text, std::size_t longest) {
  if (text.size() <= longest) return text;
  std::string start = text.substr(0, longest);
  start += "... (";
  start += std::to_string(text.size());
  start += " characters)";
  return start;
}

std::string unknown_name_message(const std::string& what, const std::string& name,
                                 const std::vector<std::string>& valid) {
  constexpr std::size_t kListAll = 12;
  // The closest names cost an edit distance each, in the product of the two lengths.
  constexpr std::size_t kLongestName = 200;
  if (name.size() > kLongestName) {
    return "unknown " + what + " '" + excerpt(name) + "'; no " + what + " has a name that long";
  }
  if (valid.empty()) return "unknown " + what + " '" + name + "'; there are none";
  if (valid.size() <= kListAll) return "unknown " + what + " '" + name + "'; valid: " + join(valid);
  return "unknown " + what + " '" + name + "'; closest: " + join(closest_names(name, valid));
}

std::string ids_text(const std::vector<std::int64_t>& ids) {
  std::string text;
  for (const std::int64_t id : ids) {
    if (!text.empty()) text += ' ';
    text += std::to_string(id);
  }
  return text;
}

std::optional<std::vector<std::int64_t>> parse_ids(std::string_view text) {
  std::vector<std::int64_t> ids;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    std::int64_t id = 0;
    const auto [end, error] = std::from_chars(text.data() + i, text.data() + text.size(), id);
    if (error != std::errc{} || id <= 0 || (end != text.data() + text.size() && *end != ' ')) return std::nullopt;
    ids.push_back(id);
    i = static_cast<std::size_t>(end - text.data());
  }
  return ids;
}

}  // namespace fleet::model
