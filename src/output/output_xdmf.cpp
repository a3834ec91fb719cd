#include <cstdio>
#include <sstream>
#include <vector>

#include "src/output/frame_fields.h"
#include "src/output/outputs.h"

namespace kiln {

namespace {

// A whole dataset of result.h5 (a per-frame view of one: /frames/k/name).
std::string item(const std::string& h5, const std::string& dataset, const std::string& dims, bool integer = false,
                 int precision = 8) {
  std::ostringstream s;
  s << "<DataItem Dimensions=\"" << dims << "\" NumberType=\"" << (integer ? "Int" : "Float") << "\" Precision=\""
    << precision << "\" Format=\"HDF\">" << h5 << ":" << dataset << "</DataItem>";
  return s.str();
}

std::string frame_view(size_t k, const char* name) { return "/frames/" + std::to_string(k) + "/" + name; }

// The Dimensions attribute of one frame of a field.
std::string frame_dims_text(const FrameFieldInfo& f, const ResultLayout& l) {
  std::string text;
  for (size_t d : frame_dims(f, l)) {
    if (!text.empty()) text += ' ';
    text += std::to_string(d);
  }
  return text;
}

}  // namespace

// Two temporal collections, `particles` and `walls`, of one uniform grid per frame, stamped with
// the frame's time. The Domain's two series keep their place (and, in the legacy reader, their
// name) at every time; a spatial collection per frame would name its grids anew per frame.
std::string xdmf_document(const std::string& h5, const ResultLayout& layout, const std::vector<double>& times) {
  const size_t n = static_cast<size_t>(layout.particles), s = static_cast<size_t>(layout.segments);
  const std::string N = std::to_string(n), S = std::to_string(s);
  std::ostringstream x;
  auto attribute = [&](const char* name, const char* type, const char* centre, const std::string& data) {
    x << "        <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << centre << "\">"
      << data << "</Attribute>\n";
  };
  auto time = [&](size_t k) {
    char t[32];
    std::snprintf(t, sizeof t, "%.17g", times[k]);
    x << "        <Time Value=\"" << t << "\"/>\n";
  };
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < times.size(); ++k) {
    x << "      <Grid Name=\"particles\" GridType=\"Uniform\">\n";
    time(k);
    // Point i is the vertex cell i (its connectivity is the id 0 .. N-1): the Xdmf3 readers make
    // no cells of a Polyvertex topology without one.
    x << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">"
      << item(h5, "/id", N, true) << "</Topology>\n"
      << "        <Geometry GeometryType=\"XYZ\">" << item(h5, frame_view(k, "position"), N + " 3")
      << "</Geometry>\n";
    attribute("radius", "Scalar", "Node", item(h5, "/radius", N));
    for (const FrameFieldInfo& f : frame_fields)
      if (f.of == FrameOf::particles && f.xdmf_attribute && in_result(f, layout))
        attribute(f.name, f.xdmf_attribute, "Node", item(h5, frame_view(k, f.name), frame_dims_text(f, layout)));
    attribute("id", "Scalar", "Node", item(h5, "/id", N, true));
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n";
  if (layout.walls > 0) {
    x << "    <Grid Name=\"walls\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (size_t k = 0; k < times.size(); ++k) {
      // Segment j joins points 2j and 2j + 1: its row (x_a, y_a, x_b, y_b) read as two XY pairs.
      x << "      <Grid Name=\"walls\" GridType=\"Uniform\">\n";
      time(k);
      x << "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << s << "\" NodesPerElement=\"2\">"
        << item(h5, "/wall_connectivity", S + " 2", true, 4) << "</Topology>\n"
        << "        <Geometry GeometryType=\"XY\">"
        << item(h5, layout.walls_move ? frame_view(k, "wall_segments") : "/wall_segments", S + " 4")
        << "</Geometry>\n";
      attribute("wall", "Scalar", "Cell", item(h5, "/wall_of_segment", S, true, 4));
      // The loads on each wall (W tuples, in the order of wall_names): field data of the frame.
      for (const FrameFieldInfo& f : frame_fields)
        if (f.of == FrameOf::walls && f.xdmf_attribute && in_result(f, layout))
          attribute(f.name, f.xdmf_attribute, "Grid",
                    item(h5, frame_view(k, f.name), frame_dims_text(f, layout)));
      x << "      </Grid>\n";
    }
    x << "    </Grid>\n";
  }
  x << "  </Domain>\n</Xdmf>\n";
  return x.str();
}

std::string units_table(const ResultLayout& layout) {
  std::ostringstream csv;
  csv << "array,series,centre,unit,dataset\n";
  auto row = [&](const char* array, const char* series, const char* centre, const char* unit, const char* dataset) {
    csv << array << ',' << series << ',' << centre << ',' << unit << ',' << dataset << '\n';
  };
  row("Points", "particles", "point", frame_field(FrameField::position).units, "position");
  row("radius", "particles", "point", "m", "radius");
  for (const FrameFieldInfo& f : frame_fields)
    if (f.of == FrameOf::particles && f.xdmf_attribute && in_result(f, layout)) row(f.name, "particles", "point", f.units, f.name);
  row("id", "particles", "point", "1", "id");
  if (layout.walls > 0) {
    row("Points", "walls", "point", frame_field(FrameField::wall_segments).units, "wall_segments");
    row("wall", "walls", "cell", "1", "wall_of_segment");
    for (const FrameFieldInfo& f : frame_fields)
      if (f.of == FrameOf::walls && f.xdmf_attribute && in_result(f, layout)) row(f.name, "walls", "field", f.units, f.name);
  }
  row("time", "both", "time step", frame_field(FrameField::time).units, "time");
  return csv.str();
}

}  // namespace kiln
