// The structure's VTU frame (structure_vtu.h).
#include "fsi/structure_vtu.h"

#include <fmt/format.h>

namespace quarry::fsi {

namespace {

constexpr int kVtkTriangle = 5, kVtkQuad = 9;  // VTK cell types

void vector_array(std::string& out, const std::string& name, std::size_t count, auto value) {
  out += fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" format=\"ascii\">\n", name);
  for (std::size_t k = 0; k < count; ++k) {
    const Vec3 v = value(k);
    out += fmt::format("          {:.17g} {:.17g} {:.17g}\n", v.x, v.y, v.z);
  }
  out += "        </DataArray>\n";
}

void scalar_array(std::string& out, const std::string& name, std::size_t count, auto value) {
  out += fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", name);
  for (std::size_t k = 0; k < count; ++k) out += fmt::format("          {:.17g}\n", value(k));
  out += "        </DataArray>\n";
}

}  // namespace

std::string structure_vtu(const fem::ShellSolver& solver, const fem::ShellModel& initial,
                          std::span<const fem::NodalLoad> loads) {
  const auto nodes = static_cast<std::size_t>(solver.node_count());
  const auto elements = static_cast<std::size_t>(solver.element_count());
  std::string out = "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                    "  <UnstructuredGrid>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", nodes, elements);
  out += "      <Points>\n";
  vector_array(out, "position", nodes, [&](std::size_t n) { return solver.positions()[n]; });
  out += "      </Points>\n      <Cells>\n";
  out += "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const fem::ShellElement& e : initial.elements) {
    out += "         ";
    for (int k = 0; k < e.node_count; ++k) out += fmt::format(" {}", e.nodes[static_cast<std::size_t>(k)]);
    out += "\n";
  }
  out += "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t offset = 0;
  for (const fem::ShellElement& e : initial.elements) {
    offset += static_cast<std::size_t>(e.node_count);
    out += fmt::format("          {}\n", offset);
  }
  out += "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (const fem::ShellElement& e : initial.elements)
    out += fmt::format("          {}\n", e.node_count == 4 ? kVtkQuad : kVtkTriangle);
  out += "        </DataArray>\n      </Cells>\n      <PointData Vectors=\"displacement\">\n";
  vector_array(out, "displacement", nodes, [&](std::size_t n) { return solver.positions()[n] - initial.nodes[n]; });
  vector_array(out, "velocity", nodes, [&](std::size_t n) { return solver.velocities()[n]; });
  vector_array(out, "load", nodes, [&](std::size_t n) { return loads.empty() ? Vec3{} : loads[n].force; });
  out += "      </PointData>\n      <CellData>\n";
  std::vector<fem::ElementResult> results(elements);
  for (std::size_t e = 0; e < elements; ++e) results[e] = solver.element_result(static_cast<int>(e));
  scalar_array(out, "von_mises_top", elements, [&](std::size_t e) { return results[e].von_mises_top; });
  scalar_array(out, "von_mises_mid", elements, [&](std::size_t e) { return results[e].von_mises_mid; });
  scalar_array(out, "von_mises_bottom", elements, [&](std::size_t e) { return results[e].von_mises_bottom; });
  scalar_array(out, "plastic_strain", elements, [&](std::size_t e) { return results[e].plastic_strain_max; });
  out += "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace quarry::fsi
