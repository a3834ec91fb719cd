#include <sstream>

#include "src/outputs.h"

namespace kiln {

std::string xdmf_document(const std::string& h5, int n, const std::vector<double>& times, bool thermal) {
  const size_t frames = times.size();
  std::ostringstream x;
  auto slab = [&](size_t k, const char* dataset, int components) {
    std::ostringstream s;
    const std::string dims = components > 1 ? std::to_string(n) + " " + std::to_string(components) : std::to_string(n);
    const std::string full = std::to_string(frames) + " " + std::to_string(n) + (components > 1 ? " 2" : "");
    s << "        <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << dims << "\" Type=\"HyperSlab\">\n"
      << "          <DataItem Dimensions=\"3 " << (components > 1 ? 3 : 2) << "\" Format=\"XML\">"
      << k << (components > 1 ? " 0 0 1 1 1 1 " : " 0 1 1 1 ") << n << (components > 1 ? " 2" : "") << "</DataItem>\n"
      << "          <DataItem Dimensions=\"" << full << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
      << ":/" << dataset << "</DataItem>\n"
      << "        </DataItem>\n";
    return s.str();
  };
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < frames; ++k) {
    char t[32];
    std::snprintf(t, sizeof t, "%.17g", times[k]);
    x << "    <Grid Name=\"frame" << k << "\" GridType=\"Uniform\">\n"
      << "      <Time Value=\"" << t << "\"/>\n"
      << "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\"/>\n"
      << "      <Geometry GeometryType=\"XY\">\n" << slab(k, "position", 2) << "      </Geometry>\n"
      << "      <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      << "        <DataItem Dimensions=\"" << n << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
      << ":/radius</DataItem>\n      </Attribute>\n"
      << "      <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
      << slab(k, "velocity", 2) << "      </Attribute>\n"
      << "      <Attribute Name=\"angular_velocity\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      << slab(k, "angular_velocity", 1) << "      </Attribute>\n";
    if (thermal)
      x << "      <Attribute Name=\"temperature\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        << slab(k, "temperature", 1) << "      </Attribute>\n";
    x << "    </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return x.str();
}

}  // namespace kiln
