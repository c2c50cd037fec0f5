#include "graph/json_util.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "graph/registry.h"

namespace orogen::json_util {

std::string format_double(double v) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back exactly
  std::string s = ec == std::errc() ? std::string(buf, end) : std::to_string(v);
  // "-0" would read back as the integer 0 and lose its sign.
  if (s == "-0") s = "-0.0";
  return s;
}

double float_as_short_double(float f) {
  if (!std::isfinite(f)) return static_cast<double>(f);
  // 9 significant digits always suffice for a float; take the fewest that survive text -> double -> float.
  for (int digits = 1; digits <= 9; ++digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(f));
    const double d = std::strtod(buf, nullptr);
    if (static_cast<float>(d) == f) return d;
  }
  return static_cast<double>(f);
}

std::string pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

namespace {

// Builds the document from SAX events, keeping the path of the value being read so that repeated keys and
// syntax errors can be located.
class StrictBuilder {
 public:
  using json = nlohmann::json;
  StrictBuilder(std::string_view text, std::vector<ParseProblem>& problems) : text_(text), problems_(problems) {}

  bool null() { return add(json(nullptr)); }
  bool boolean(bool v) { return add(json(v)); }
  bool number_integer(json::number_integer_t v) { return add(json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return add(json(v)); }
  bool number_float(json::number_float_t v, const std::string&) { return add(json(v)); }
  bool string(std::string& v) { return add(json(std::move(v))); }
  bool binary(json::binary_t& v) { return add(json::binary(std::move(v))); }

  bool start_object(std::size_t) {
    stack_.push_back({json::object(), true, {}, {}, 0});
    return true;
  }
  bool key(std::string& k) {
    Frame& f = stack_.back();
    if (!f.keys.insert(k).second)
      problems_.push_back({container_path() + "/" + pointer_token(k),
                           "duplicate key '" + k + "': each key may appear only once in an object"});
    f.key = k;
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) {
    stack_.push_back({json::array(), false, {}, {}, 0});
    return true;
  }
  bool end_array() { return close(); }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& ex) {
    // what() is "[json.exception.parse_error.101] parse error at line 3, column 5: <detail>"; keep the detail.
    std::string detail = ex.what();
    if (const auto bracket = detail.find("] "); bracket != std::string::npos) detail = detail.substr(bracket + 2);
    if (detail.rfind("parse error", 0) == 0)
      if (const auto colon = detail.find(": "); colon != std::string::npos) detail = detail.substr(colon + 2);
    // `position` counts the characters read; turn it into a line and column the way an editor shows them.
    const std::string_view read = text_.substr(0, std::min(position, text_.size()));
    const auto line = 1 + static_cast<std::size_t>(std::count(read.begin(), read.end(), '\n'));
    const auto last_newline = read.rfind('\n');
    const auto column = last_newline == std::string_view::npos ? read.size() : read.size() - last_newline - 1;
    syntax_error_ = true;
    // A number too large is located by its path; a syntax error only by line and column, since the path
    // of the last value read is often not where the mistake is (a missing comma after it, say).
    const bool number_overflow = ex.id == 406;
    problems_.push_back(
        {number_overflow ? path() : std::string(),
         "malformed JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + detail});
    return false;
  }

  bool syntax_error() const { return syntax_error_; }
  json take() { return std::move(root_); }

 private:
  struct Frame {
    json value;
    bool is_object;
    std::string key;
    std::set<std::string> keys;
    std::size_t index;
  };

  // The path of the value being read.
  std::string path() const { return path_of(stack_.size()); }
  // The path of the innermost object or array.
  std::string container_path() const { return path_of(stack_.empty() ? 0 : stack_.size() - 1); }

  std::string path_of(std::size_t levels) const {
    std::string p;
    for (std::size_t i = 0; i < levels; ++i) {
      const Frame& f = stack_[i];
      p += '/';
      p += f.is_object ? pointer_token(f.key) : std::to_string(f.index);
    }
    return p;
  }

  bool add(json v) {
    if (stack_.empty()) {
      root_ = std::move(v);
      return true;
    }
    Frame& f = stack_.back();
    if (f.is_object) {
      f.value[f.key] = std::move(v);
    } else {
      f.value.push_back(std::move(v));
      ++f.index;
    }
    return true;
  }

  bool close() {
    json v = std::move(stack_.back().value);
    stack_.pop_back();
    return add(std::move(v));
  }

  std::string_view text_;
  std::vector<ParseProblem>& problems_;
  std::vector<Frame> stack_;
  json root_;
  bool syntax_error_ = false;
};

}  // namespace

std::optional<nlohmann::json> parse_strict(std::string_view text, std::vector<ParseProblem>& problems) {
  StrictBuilder builder(text, problems);
  bool ok = false;
  try {
    ok = nlohmann::json::sax_parse(text, &builder, nlohmann::json::input_format_t::json, true, false);
  } catch (const nlohmann::json::exception& e) {
    problems.push_back({"", std::string("malformed JSON: ") + e.what()});
    return std::nullopt;
  }
  if (!ok || builder.syntax_error()) return std::nullopt;
  return builder.take();
}

std::string describe(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::boolean:
      return j.get<bool>() ? "true" : "false";
    case nlohmann::json::value_t::string: {
      std::string s = j.get<std::string>();
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return "the string \"" + s + "\"";
    }
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return "the number " + j.dump();
    case nlohmann::json::value_t::number_float: {
      // Say "1.0", not "1", so that a message about a non-integer does not show an integer.
      std::string text = format_double(j.get<double>());
      if (text.find_first_of(".en") == std::string::npos) text += ".0";
      return "the number " + text;
    }
    case nlohmann::json::value_t::array:
      return j.size() == 1 ? "an array of 1 element" : "an array of " + std::to_string(j.size()) + " elements";
    case nlohmann::json::value_t::object:
      return "an object";
    default:
      return "a " + std::string(j.type_name()) + " value";
  }
}

std::string closest_name(std::string_view name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(3, name.size() / 2) + 1;
  for (const auto& c : candidates) {
    const auto d = edit_distance(name, c);
    // A distance as large as the words themselves means "unrelated", not "typo".
    if (d < best_distance && d < std::max(name.size(), c.size())) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

std::string suggestion(std::string_view name, const std::vector<std::string>& candidates) {
  if (candidates.empty()) return {};
  if (auto best = closest_name(name, candidates); !best.empty()) return " (did you mean '" + best + "'?)";
  std::string all;
  for (const auto& c : candidates) all += (all.empty() ? "" : ", ") + c;
  return " (expected one of: " + all + ")";
}

}  // namespace orogen::json_util
