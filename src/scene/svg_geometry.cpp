// SVG wall geometry: pugixml parses the XML; this file walks the document (namespaces, layers and
// groups, hidden elements, the root's viewBox) and hands each drawing element to its shape's
// reader (svg_parts.h). Section numbers refer to SVG 1.1 (Second Edition), 2011.
#include "src/scene/svg_geometry.h"

#include "src/scene/svg_parts.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <pugixml.hpp>

#include "src/base/error.h"

namespace kiln {

namespace {

using namespace svg;

constexpr std::string_view svg_namespace = "http://www.w3.org/2000/svg";
constexpr std::string_view inkscape_namespace = "http://www.inkscape.org/namespaces/inkscape";
constexpr int max_depth = 1000;  // keeps the recursive walk far from the end of the stack

std::string_view prefix_of(std::string_view name) {
  const size_t colon = name.find(':');
  return colon == std::string_view::npos ? std::string_view() : name.substr(0, colon);
}

std::string_view local_of(std::string_view name) {
  const size_t colon = name.find(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

// The namespace bound to `prefix` where n stands (Namespaces in XML 1.0), or nullptr.
const char* namespace_at(pugi::xml_node n, std::string_view prefix) {
  const std::string declaration = prefix.empty() ? "xmlns" : "xmlns:" + std::string(prefix);
  for (; n; n = n.parent())
    if (const pugi::xml_attribute a = n.attribute(declaration.c_str())) return a.value();
  return nullptr;
}

// A file that declares no namespace at all (hand-written) is taken as SVG while it uses no prefix.
bool in_svg_namespace(pugi::xml_node n) {
  const std::string_view prefix = prefix_of(n.name());
  const char* uri = namespace_at(n, prefix);
  return uri ? uri == svg_namespace : prefix.empty();
}

bool is_layer(pugi::xml_node g) {
  for (const pugi::xml_attribute a : g.attributes()) {
    const std::string_view name = a.name();
    if (local_of(name) != "groupmode" || prefix_of(name).empty()) continue;
    const char* uri = namespace_at(g, prefix_of(name));
    if (uri && uri == inkscape_namespace && std::string_view(a.value()) == "layer") return true;
  }
  return false;
}

std::string_view trimmed(std::string_view s) {
  const size_t first = s.find_first_not_of(" \t\n\r");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\n\r") - first + 1);
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  });
}

// display="none", or display:none among the style attribute's declarations (CSS keywords and
// property names are case-insensitive; "!important" does not change the value).
bool hidden(pugi::xml_node n) {
  if (equals_ignoring_case(trimmed(n.attribute("display").value()), "none")) return true;
  std::string_view style = n.attribute("style").value();
  while (!style.empty()) {
    const size_t end = std::min(style.find(';'), style.size());
    const std::string_view declaration = style.substr(0, end);
    style.remove_prefix(std::min(end + 1, style.size()));
    const size_t colon = declaration.find(':');
    if (colon == std::string_view::npos) continue;
    std::string_view value = trimmed(declaration.substr(colon + 1));
    value = trimmed(value.substr(0, value.find('!')));
    if (equals_ignoring_case(trimmed(declaration.substr(0, colon)), "display") && equals_ignoring_case(value, "none"))
      return true;
  }
  return false;
}

// SVG 1.1 elements that never draw where they stand (definitions, descriptions, resources) or
// only animate what does.
bool draws_nothing(std::string_view name) {
  static constexpr std::array<std::string_view, 26> names{
      "defs", "metadata", "title", "desc", "style", "script", "symbol", "marker", "clipPath",
      "mask", "pattern", "linearGradient", "radialGradient", "filter", "font", "font-face",
      "color-profile", "cursor", "view", "animate", "animateColor", "animateMotion",
      "animateTransform", "set", "altGlyphDef", "mpath"};
  return std::find(names.begin(), names.end(), name) != names.end();
}

// "path 'flight3'", or the tag alone when the element has no id.
std::string describe(pugi::xml_node n) {
  const std::string id = n.attribute("id").value();
  return std::string(n.name()) + (id.empty() ? "" : " '" + id + "'");
}

// What encloses an element: the map to the world and its group.
struct Scope {
  Affine to_world;
  std::optional<std::string> group;  // the nearest enclosing <g> with an id that is no layer
  std::string layer;                 // the nearest enclosing layer's id
  const std::string& group_id() const { return group ? *group : layer; }
};

class Reader {
 public:
  Reader(std::string path, std::string text, const SvgPlacement& placement)
      : path_(std::move(path)), text_(std::move(text)), placement_(placement), budget_(placement.tolerance) {}

  std::vector<SvgGroup> read() {
    if (text_.find('\0') != std::string::npos)
      throw InputError(Location{path_, 0, ""}, "is not UTF-8 text (it holds NUL bytes; UTF-16 is not read)");
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed =
        doc.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed) fail_at(parsed.offset, std::string("not well-formed XML: ") + parsed.description());
    const pugi::xml_node root = the_root(doc);
    if (!hidden(root)) read_children(root, Scope{placed(root), std::nullopt, ""}, 0);
    if (groups_.empty())
      throw InputError(Location{path_, 0, ""},
                       "holds no path, line, polyline, polygon, rect, circle or ellipse (none drawn, visible and "
                       "longer than a point)");
    return std::move(groups_);
  }

 private:
  [[noreturn]] void fail_at(ptrdiff_t offset, const std::string& message) const {
    const auto end = text_.begin() + std::clamp<ptrdiff_t>(offset, 0, static_cast<ptrdiff_t>(text_.size()));
    throw InputError(Location{path_, 1 + static_cast<int>(std::count(text_.begin(), end, '\n')), ""}, message);
  }
  [[noreturn]] void fail(pugi::xml_node n, const std::string& message) const {
    fail_at(n.offset_debug(), describe(n) + ": " + message);
  }

  pugi::xml_node the_root(const pugi::xml_document& doc) const {
    const pugi::xml_node root = doc.document_element();
    for (pugi::xml_node n = root.next_sibling(); n; n = n.next_sibling())
      if (n.type() == pugi::node_element) fail_at(n.offset_debug(), "not well-formed XML: a second root element");
    if (!in_svg_namespace(root) || local_of(root.name()) != "svg")
      fail(root, "the root element is not an <svg> of the SVG namespace (" + std::string(svg_namespace) + ")");
    if (root.attribute("transform")) fail(root, "a transform on the root <svg> is not read: put it on a <g>");
    return root;
  }

  // The map from the root's user units to the world (see read_svg_walls).
  Affine placed(pugi::xml_node root) const {
    double left = 0, bottom = 0;
    try {
      if (const pugi::xml_attribute box = root.attribute("viewBox")) {
        const std::vector<double> v = number_list(box.value());
        if (v.size() != 4) throw Malformed("viewBox needs 4 numbers, found " + std::to_string(v.size()));
        if (!(v[2] > 0 && v[3] > 0)) throw Malformed("viewBox width and height must be > 0");
        left = v[0];
        bottom = v[1] + v[3];
      } else {
        bottom = length_attribute(root, "height").value_or(0);
      }
    } catch (const Malformed& e) {
      fail(root, e.what());
    }
    const double s = placement_.scale;
    return {s, 0, 0, -s, placement_.offset.x - s * left, placement_.offset.y + s * bottom};
  }

  void read_children(pugi::xml_node parent, const Scope& scope, int depth) {
    for (const pugi::xml_node n : parent.children()) {
      if (n.type() != pugi::node_element || !in_svg_namespace(n) || hidden(n)) continue;
      const std::string_view name = local_of(n.name());
      if (draws_nothing(name)) continue;
      if (name == "g") {
        if (depth >= max_depth) fail(n, "groups are nested more than 1000 deep");
        read_children(n, inside(n, scope), depth + 1);
      } else if (const ShapeReader reader = shape_reader(name)) {
        read_shape(n, reader, scope);
      } else {
        fail(n, "is not read: only path, line, polyline, polygon, rect, circle and ellipse elements (in g groups) are");
      }
    }
  }

  Scope inside(pugi::xml_node g, const Scope& outer) const {
    Scope scope = outer;
    scope.to_world = with_transform(g, outer.to_world);
    const std::string id = g.attribute("id").value();
    if (is_layer(g))
      scope.layer = id;
    else if (!id.empty())
      scope.group = id;
    return scope;
  }

  Affine with_transform(pugi::xml_node n, const Affine& outer) const {
    const pugi::xml_attribute t = n.attribute("transform");
    if (!t) return outer;
    try {
      return composed(outer, t.value());
    } catch (const Malformed& e) {
      fail(n, "transform " + excerpt(t.value()) + ": " + e.what());
    }
  }

  void read_shape(pugi::xml_node n, ShapeReader reader, const Scope& scope) {
    Pen pen{with_transform(n, scope.to_world), Trace(budget_, placement_.tolerance), {}};
    try {
      reader(n, pen);
    } catch (const Malformed& e) {
      fail(n, e.what());
    }
    if (!pen.lines.empty()) add(scope.group_id(), std::move(pen.lines));
  }

  // A group is made when it first gets lines, so that every group returned has some.
  void add(const std::string& id, std::vector<SvgPolyline> lines) {
    const auto [at, fresh] = index_.try_emplace(id, groups_.size());
    if (fresh) groups_.push_back(SvgGroup{id, {}});
    std::vector<SvgPolyline>& all = groups_[at->second].lines;
    std::move(lines.begin(), lines.end(), std::back_inserter(all));
  }

  std::string path_;
  std::string text_;
  SvgPlacement placement_;
  Budget budget_;
  std::vector<SvgGroup> groups_;
  std::map<std::string, size_t> index_;
};

// A drawing is a regular file of at most 64 MiB: a device (/dev/zero) or a pipe would never end.
std::string read_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InputError(Location{path, 0, ""}, "is not a regular file");
  constexpr std::uintmax_t largest = std::uintmax_t{64} << 20;
  if (!ec && std::filesystem::is_regular_file(status) && std::filesystem::file_size(path, ec) > largest)
    throw InputError(Location{path, 0, ""}, "is larger than 64 MiB: not a drawing of walls");
  std::ifstream in(path, std::ios::binary);
  try {
    if (in) return std::string(std::istreambuf_iterator<char>(in), {});
  } catch (const std::ios_base::failure&) {
    // a directory opens but cannot be read; errno says why
  }
  throw InputError(Location{path, 0, ""}, std::string("cannot be read: ") + std::strerror(errno));
}

void check_placement(const std::string& path, const SvgPlacement& p) {
  const auto refuse = [&](const std::string& what) { throw InputError(Location{path, 0, ""}, what); };
  if (!(std::isfinite(p.scale) && p.scale > 0))
    refuse("the scale must be a finite number > 0 (metres per user unit), got " + message_number(p.scale));
  if (!(std::isfinite(p.tolerance) && p.tolerance > 0))
    refuse("the tolerance must be a finite number > 0 (metres), got " + message_number(p.tolerance));
  if (!(std::isfinite(p.offset.x) && std::isfinite(p.offset.y))) refuse("the offset must be finite");
}

}  // namespace

std::vector<SvgGroup> read_svg_walls(const std::string& path, const SvgPlacement& placement) {
  check_placement(path, placement);
  return Reader(path, read_file(path), placement).read();
}

}  // namespace kiln
