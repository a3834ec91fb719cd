// The micro-syntaxes inside attribute values: numbers, flags and punctuation (the path data
// grammar, section 8.3.9), number lists, lengths (section 4.2), and the texts of messages.
#include "src/scene/svg_parts.h"

#include <cctype>
#include <charconv>
#include <cstring>
#include <map>

namespace kiln::svg {

// A character for a message; a byte that is not printable ASCII (part of a UTF-8 sequence, say)
// by its code.
std::string quoted(char c) {
  const auto byte = static_cast<unsigned char>(c);
  if (std::isprint(byte)) return std::string("'") + c + "'";
  static constexpr char hex[] = "0123456789ABCDEF";
  return std::string("byte 0x") + hex[byte >> 4] + hex[byte & 15];
}

bool one_of(char c, std::string_view set) { return set.find(c) != std::string_view::npos; }

// The text of an attribute for a message, shortened: path data can be megabytes long.
std::string excerpt(std::string_view text) {
  constexpr size_t longest = 60;
  std::string shown = "\"";  // appended, not concatenated: GCC 12 warns wrongly on `+` here (-Wrestrict)
  shown += text.substr(0, longest);
  shown += text.size() > longest ? "...\"" : "\"";
  return shown;
}

double Scanner::number() {
  skip_space();
  const size_t start = pos_;
  if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
  size_t mantissa = digits();
  if (pos_ < text_.size() && text_[pos_] == '.') {
    ++pos_;
    mantissa += digits();
  }
  if (mantissa == 0) {
    pos_ = start;
    throw unexpected("expected a number");
  }
  if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
    ++pos_;
    if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
    if (digits() == 0)
      throw Malformed("the number '" + std::string(text_.substr(start, pos_ - start)) + "' ending before " +
                      where() + " has an exponent without digits");
  }
  // from_chars: exact and independent of the locale; it takes no leading '+'.
  const char* first = text_.data() + start + (text_[start] == '+' ? 1 : 0);
  double value = 0;
  const auto [end, status] = std::from_chars(first, text_.data() + pos_, value);
  if (status != std::errc() || !std::isfinite(value))
    throw Malformed("the number '" + std::string(text_.substr(start, pos_ - start)) +
                    "' is beyond the range of double precision (not finite)");
  after_value_ = true;
  return value;
}

// All the numbers of a list (points, viewBox); the text must hold nothing else.
std::vector<double> number_list(std::string_view text) {
  Scanner s(text);
  std::vector<double> values;
  while (s.at_number()) values.push_back(s.number());
  if (!s.at_end()) throw s.unexpected("expected a number");
  return values;
}

// A <length> (section 4.2) in user units: a number with px or no unit, or an absolute unit at 96 px
// per inch (CSS 2.1 and SVG 2; SVG 1.1 still said 90, browsers and Inkscape 0.92+ use 96).
double length_value(std::string_view text) {
  Scanner s(text);
  if (!s.at_number()) throw s.unexpected("expected a length");
  const double value = s.number();
  if (s.accept('%')) throw Malformed("a length in % needs the viewport, which is not read");
  const std::string_view unit = s.word();
  if (!s.at_end()) throw s.unexpected("expected the end of the length");
  static const std::map<std::string_view, double> px_per_unit{
      {"", 1}, {"px", 1}, {"in", 96}, {"cm", 96 / 2.54}, {"mm", 96 / 25.4}, {"pt", 96.0 / 72}, {"pc", 16}};
  const auto known = px_per_unit.find(unit);
  if (known == px_per_unit.end())
    throw Malformed("unit '" + std::string(unit) + "' is not read (px, in, cm, mm, pt and pc are)");
  return value * known->second;
}

}  // namespace kiln::svg
