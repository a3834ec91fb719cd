#include <cstdio>
#include <sstream>
#include <vector>

#include "src/output/frame_fields.h"
#include "src/output/outputs.h"

namespace kiln {

namespace {

// A whole dataset of result.h5.
std::string whole(const std::string& h5, const char* dataset, const std::string& dims, bool integer = false,
                  int precision = 8) {
  std::ostringstream s;
  s << "<DataItem Dimensions=\"" << dims << "\" NumberType=\"" << (integer ? "Int" : "Float") << "\" Precision=\""
    << precision << "\" Format=\"HDF\">" << h5 << ":/" << dataset << "</DataItem>";
  return s.str();
}

// Frame k of a dataset of `frames` frames of shape `frame` (one or two sizes): a HyperSlab whose
// result has the frame's shape.
std::string frame_of(const std::string& h5, const char* dataset, size_t k, size_t frames, std::vector<size_t> frame,
                     const std::string& indent) {
  const size_t rank = frame.size() + 1;
  std::ostringstream dims, start, stride, count;
  start << k;
  stride << 1;
  count << 1;
  for (size_t i = 0; i < frame.size(); ++i) {
    dims << (i ? " " : "") << frame[i];
    start << " 0";
    stride << " 1";
    count << " " << frame[i];
  }
  std::ostringstream s;
  s << indent << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << dims.str() << "\" Type=\"HyperSlab\">\n"
    << indent << "  <DataItem Dimensions=\"3 " << rank << "\" Format=\"XML\">" << start.str() << " " << stride.str()
    << " " << count.str() << "</DataItem>\n"
    << indent << "  " << whole(h5, dataset, std::to_string(frames) + " " + dims.str()) << "\n"
    << indent << "</DataItem>\n";
  return s.str();
}

}  // namespace

// Per frame: a spatial collection (stamped with the frame's time) of the particles and the walls.
std::string xdmf_document(const std::string& h5, const ResultLayout& layout, const std::vector<double>& times) {
  const size_t frames = times.size(), n = static_cast<size_t>(layout.particles),
               s = static_cast<size_t>(layout.segments);
  const std::string in = "            ";  // the DataItems of an Attribute or Geometry
  std::ostringstream x;
  auto attribute = [&](const char* name, const char* type, const char* centre, const std::string& item) {
    x << "          <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << centre << "\">\n"
      << item << "          </Attribute>\n";
  };
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"kiln\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < frames; ++k) {
    char t[32];
    std::snprintf(t, sizeof t, "%.17g", times[k]);
    x << "      <Grid Name=\"frame" << k << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      << "        <Time Value=\"" << t << "\"/>\n"
      << "        <Grid Name=\"particles\" GridType=\"Uniform\">\n"
      << "          <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\"/>\n"
      << "          <Geometry GeometryType=\"XYZ\">\n"
      << frame_of(h5, "position", k, frames, {n, 3}, in) << "          </Geometry>\n";
    attribute("radius", "Scalar", "Node", in + whole(h5, "radius", std::to_string(n)) + "\n");
    for (const FrameFieldInfo& f : frame_fields) {
      if (f.of != FrameOf::particles || !f.xdmf_attribute) continue;
      if (f.when == FramePresence::thermal && !layout.thermal) continue;
      const bool vector = f.layout != FrameLayout::scalar;
      attribute(f.name, f.xdmf_attribute, "Node",
                frame_of(h5, f.name, k, frames, vector ? std::vector<size_t>{n, 3} : std::vector<size_t>{n}, in));
    }
    attribute("id", "Scalar", "Node", in + whole(h5, "id", std::to_string(n), true, 8) + "\n");
    x << "        </Grid>\n";
    if (layout.walls > 0) {
      // Segment j joins points 2j and 2j + 1: its row (x_a, y_a, x_b, y_b) read as two XY pairs.
      x << "        <Grid Name=\"walls\" GridType=\"Uniform\">\n"
        << "          <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << s << "\" NodesPerElement=\"2\">\n"
        << in << whole(h5, "wall_connectivity", std::to_string(s) + " 2", true, 4) << "\n"
        << "          </Topology>\n"
        << "          <Geometry GeometryType=\"XY\">\n"
        << (layout.walls_move ? frame_of(h5, "wall_segments", k, frames, {s, 4}, in)
                              : in + whole(h5, "wall_segments", std::to_string(s) + " 4") + "\n")
        << "          </Geometry>\n";
      attribute("wall", "Scalar", "Cell", in + whole(h5, "wall_of_segment", std::to_string(s), true, 4) + "\n");
      x << "        </Grid>\n";
    }
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return x.str();
}

}  // namespace kiln
