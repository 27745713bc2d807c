#pragma once
// An independent reader of the VTK XML frames ppohdem writes (docs/formats.md "VTK XML
// frames"), for tests: it parses the XML header with regular expressions, finds the appended
// block after "_" and reads each array as [UInt64 byte count][bytes], checking the counts
// against NumberOfPoints and the declared type and components. It shares no code with the
// writer (core/src/dem/vtu_writer.cpp).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::test {

struct VtuArrayRead {
  std::string type;
  int components = 1;
  std::vector<unsigned char> bytes;
};

struct VtuRead {
  std::size_t points = 0;
  std::size_t cells = 0;
  std::map<std::string, VtuArrayRead> arrays;  ///< by Name; the points under "Points"
};

inline std::string read_whole_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + file.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string xml_attribute_of(const std::string& element, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(element, m, std::regex("\\b" + name + "=\"([^\"]*)\""))) return "";
  return m[1].str();
}

inline std::size_t vtk_type_size(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes = {{"Float64", 8}, {"Int64", 8}, {"UInt64", 8}, {"Float32", 4},
                                                           {"Int32", 4},   {"UInt16", 2}, {"UInt8", 1}};
  const auto it = sizes.find(type);
  if (it == sizes.end()) throw std::runtime_error("unknown VTK type " + type);
  return it->second;
}

inline VtuRead read_vtu(const std::filesystem::path& file) {
  const std::string text = read_whole_file(file);
  const std::string appended = "<AppendedData encoding=\"raw\">";
  const auto a = text.find(appended);
  if (a == std::string::npos) throw std::runtime_error(file.string() + ": no raw AppendedData");
  const auto underscore = text.find('_', a + appended.size());
  if (underscore == std::string::npos) throw std::runtime_error(file.string() + ": no '_' before the data");
  const std::string xml = text.substr(0, a);
  if (xml_attribute_of(xml, "header_type") != "UInt64" || xml_attribute_of(xml, "byte_order") != "LittleEndian" ||
      xml.find("type=\"UnstructuredGrid\"") == std::string::npos) {
    throw std::runtime_error(file.string() + ": not a LittleEndian UInt64-header UnstructuredGrid");
  }
  VtuRead out;
  out.points = std::stoull(xml_attribute_of(xml, "NumberOfPoints"));
  out.cells = std::stoull(xml_attribute_of(xml, "NumberOfCells"));
  const char* data = text.data() + underscore + 1;
  const std::size_t available = text.size() - underscore - 1;
  std::size_t end_of_data = 0;
  const std::regex element("<DataArray ([^>]*)/>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), element); it != std::sregex_iterator(); ++it) {
    const std::string e = (*it)[1].str();
    if (xml_attribute_of(e, "format") != "appended") throw std::runtime_error(file.string() + ": an array not appended");
    std::string name = xml_attribute_of(e, "Name");
    if (name.empty()) name = "Points";
    VtuArrayRead array;
    array.type = xml_attribute_of(e, "type");
    const std::string components = xml_attribute_of(e, "NumberOfComponents");
    array.components = components.empty() ? 1 : std::stoi(components);
    const std::size_t offset = std::stoull(xml_attribute_of(e, "offset"));
    if (offset + 8 > available) throw std::runtime_error(file.string() + ": offset past the data: " + name);
    std::uint64_t count = 0;
    std::memcpy(&count, data + offset, 8);
    const std::size_t rows = (name == "connectivity" || name == "offsets" || name == "types") ? out.cells : out.points;
    if (count != rows * static_cast<std::size_t>(array.components) * vtk_type_size(array.type)) {
      throw std::runtime_error(file.string() + ": array " + name + " has " + std::to_string(count) + " bytes");
    }
    if (offset + 8 + count > available) throw std::runtime_error(file.string() + ": array past the end: " + name);
    array.bytes.assign(data + offset + 8, data + offset + 8 + count);
    end_of_data = std::max<std::size_t>(end_of_data, offset + 8 + count);
    out.arrays[name] = std::move(array);
  }
  if (std::string(data + end_of_data, available - end_of_data).find("</AppendedData>") == std::string::npos) {
    throw std::runtime_error(file.string() + ": no </AppendedData> after the data");
  }
  return out;
}

template <class T>
T vtu_value(const VtuArrayRead& a, std::size_t index) {
  T v;
  std::memcpy(&v, a.bytes.data() + index * sizeof(T), sizeof(T));
  return v;
}

/// The particles of a piece (force and torque included).
inline ppohdem::dem::Particles particles_of(const VtuRead& r) {
  ppohdem::dem::Particles p(r.points);
  auto vec = [&](const char* name, std::size_t i) {
    const VtuArrayRead& a = r.arrays.at(name);
    return ppohdem::Vec3(vtu_value<double>(a, 3 * i), vtu_value<double>(a, 3 * i + 1), vtu_value<double>(a, 3 * i + 2));
  };
  for (std::size_t i = 0; i < r.points; ++i) {
    p[i].id = vtu_value<std::int64_t>(r.arrays.at("id"), i);
    p[i].position = vec("Points", i);
    p[i].velocity = vec("velocity", i);
    p[i].angular_velocity = vec("angular_velocity", i);
    p[i].radius = vtu_value<double>(r.arrays.at("radius"), i);
    p[i].material = vtu_value<std::uint16_t>(r.arrays.at("material"), i);
    p[i].force = vec("force", i);
    p[i].torque = vec("torque", i);
  }
  return p;
}

/// The Source (pvtu) or file (pvd) attributes of an index, in order.
inline std::vector<std::string> listed_files(const std::filesystem::path& index, const std::string& attribute) {
  const std::string text = read_whole_file(index);
  std::vector<std::string> files;
  const std::regex re(attribute + "=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) files.push_back((*it)[1].str());
  return files;
}

}  // namespace ppohdem::test
