#include "common/args.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace fleet {

std::optional<std::string> Args::value(const std::string& name) {
  const std::string flag_name = "--" + name;
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (args_[i] == flag_name) {
      if (i + 1 >= args_.size()) throw ArgError("flag " + flag_name + " needs a value");
      std::string v = args_[i + 1];
      args_.erase(args_.begin() + static_cast<long>(i), args_.begin() + static_cast<long>(i) + 2);
      return v;
    }
    if (args_[i].rfind(flag_name + "=", 0) == 0) {
      std::string v = args_[i].substr(flag_name.size() + 1);
      args_.erase(args_.begin() + static_cast<long>(i));
      return v;
    }
  }
  return std::nullopt;
}

std::optional<std::string> Args::peek(const std::string& name) const {
  const std::string flag_name = "--" + name;
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (args_[i] == flag_name && i + 1 < args_.size()) return args_[i + 1];
    if (args_[i].rfind(flag_name + "=", 0) == 0) return args_[i].substr(flag_name.size() + 1);
  }
  return std::nullopt;
}

bool Args::flag(const std::string& name) {
  for (std::size_t i = 0; i < args_.size(); ++i) {
    if (args_[i] == "--" + name) {
      args_.erase(args_.begin() + static_cast<long>(i));
      return true;
    }
  }
  return false;
}

namespace {

/// std::from_chars over the whole of `text`; nothing when it stops early or fails.
template <class T>
std::optional<T> parse_whole(const std::string& text) {
  T v{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return v;
}

}  // namespace

std::optional<double> parse_finite(const std::string& text) {
  const auto v = parse_whole<double>(text);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

std::optional<long> parse_long(const std::string& text) {
  return parse_whole<long>(text);
}

std::optional<std::uint64_t> parse_u64(const std::string& text) {
  return parse_whole<std::uint64_t>(text);
}

std::uint64_t parse_u64(const std::string& name, const std::string& text) {
  const auto v = parse_u64(text);
  if (!v) throw ArgError("flag --" + name + ": '" + text + "' is not a non-negative integer");
  return *v;
}

std::string format_number(double value) {
  if (std::isfinite(value) && value == std::floor(value) && std::abs(value) < 1e15) {
    return std::to_string(static_cast<long long>(value));
  }
  std::ostringstream out;
  out << std::setprecision(10) << value;
  return out.str();
}

std::optional<double> Args::number(const std::string& name, double min, double max) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  const auto parsed = parse_finite(*text);
  if (!parsed) throw ArgError("flag --" + name + ": '" + *text + "' is not a number");
  const double v = *parsed;
  if (v < min || v > max) {
    throw ArgError("flag --" + name + ": " + *text + " is outside " + format_number(min) + " .. " + format_number(max));
  }
  return v;
}

std::optional<long> Args::integer(const std::string& name, long min, long max) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  const auto parsed = parse_long(*text);
  if (!parsed) throw ArgError("flag --" + name + ": '" + *text + "' is not an integer");
  const long v = *parsed;
  if (v < min || v > max) {
    throw ArgError("flag --" + name + ": " + *text + " is outside " + std::to_string(min) + " .. " +
                   std::to_string(max));
  }
  return v;
}

std::optional<std::uint64_t> Args::u64(const std::string& name) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  return parse_u64(name, *text);
}

bool looks_like_flag(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && !std::isdigit(static_cast<unsigned char>(word[1])) && word[1] != '.';
}

std::vector<std::string> Args::positionals() const {
  for (const auto& a : args_) {
    if (looks_like_flag(a)) throw ArgError("unknown flag '" + a + "'");
  }
  return args_;
}

}  // namespace fleet
