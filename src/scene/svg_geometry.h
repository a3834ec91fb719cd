// Wall geometry drawn in an SVG file (Inkscape or any editor), read into world coordinates as
// polylines. Source: W3C, "Scalable Vector Graphics (SVG) 1.1 (Second Edition)", Recommendation,
// 16 August 2011: chapter 7 (Coordinate Systems, Transformations and Units), chapter 8 (Paths),
// chapter 9 (Basic Shapes) and appendix F.6 (elliptical arc implementation notes). Section numbers
// below refer to it.
#pragma once
#include <string>
#include <vector>

#include "src/base/vec2.h"

namespace kiln {

// One polyline in world coordinates (metres). No two consecutive points coincide (points closer
// than 1e-6 x tolerance are merged: far below the accuracy asked for, and it keeps zero-length
// segments out). A closed polyline does not repeat its first point at the end.
struct SvgPolyline {
  std::vector<Vec2> points;  // at least 2
  bool closed = false;
};

// The lines of one group, in document order. The group of an element is the nearest enclosing
// <g> that has an id and is not an Inkscape layer (inkscape:groupmode="layer"); an element in no
// such group belongs to its nearest enclosing layer's id, or to "" when that layer has no id or
// there is none. Groups sharing an id are one group.
struct SvgGroup {
  std::string id;
  std::vector<SvgPolyline> lines;
};

// Where the drawing goes in the world.
struct SvgPlacement {
  double scale = 1;       // metres per SVG user unit, > 0
  Vec2 offset{0, 0};      // metres: where the lower-left corner of the drawing lands
  double tolerance = 0;   // metres, > 0: the largest distance between a curve and its chords
};

// Reads every drawn path, line, polyline, polygon, rect, circle and ellipse of the SVG file at
// `path` (UTF-8) and returns its groups in document order of first appearance.
//
// World coordinates: user units (after every `transform` of the element and of each enclosing
// <g>, section 7.6: matrix, translate, scale, rotate, skewX, skewY) are scaled by `scale`, y is
// flipped (SVG's y points down) and the lower-left corner of the root's viewBox lands at `offset`:
//   world = offset + scale * (x - vb_x, (vb_y + vb_h) - y).
// Without a viewBox the root's width and height stand for it (vb = 0 0 width height; lengths in
// px, in, cm, mm, pt or pc at 96 px per inch, as browsers and Inkscape 0.92+ read them); with
// neither, world = offset + scale * (x, -y).
//
// Paths (chapter 8): M L H V C S Q T A Z, absolute and relative, with implicit repeated commands;
// each subpath is one polyline, closed by Z. Arcs follow appendix F.6: radii too small for their
// end points are scaled up, a zero radius draws a straight line and equal end points draw nothing.
// Basic shapes (chapter 9): rect (with rx/ry rounded corners, clamped to half the side), circle,
// ellipse (closed); line and polyline (open); polygon (closed).
//
// Curves (Beziers, arcs, circles, ellipses, rounded corners) are flattened after being mapped to
// world coordinates, so that no chord departs from the true curve by more than `tolerance`; straight
// pieces keep their exact end points. A full circle or ellipse has at least 3 points.
//
// Not read, silently: defs, metadata, title, desc, style, script, symbol, marker, clipPath, mask,
// pattern, gradients, filter, font, cursor, view, animations (the static drawing is read), anything
// outside the SVG namespace (inkscape:*, sodipodi:*), and elements hidden by display="none" or a
// style attribute with display:none, with all they contain. CSS in <style> is not applied.
//
// Throws InputError, its message starting with the file and, for a fault in the file, its line:
// file not readable, not UTF-8 (NUL bytes) or not well-formed XML (the parser's description); root
// not <svg>, or one with a transform; any other element that draws (text, image, use, a, switch,
// a nested svg, ...), named with its tag, id and line; malformed path data (the command and what is
// wrong), points, viewBox, length or transform; a non-finite number; a singular transform; a
// missing, zero or negative width, height or radius; more than 1,000 levels of nesting; more than
// 1,000,000 points in all (use a larger tolerance); a file with nothing drawn; and a scale or
// tolerance that is not a finite number > 0.
std::vector<SvgGroup> read_svg_walls(const std::string& path, const SvgPlacement& placement);

}  // namespace kiln
