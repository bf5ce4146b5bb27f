// Tests of the STL reader/writer: ASCII and binary detection (a binary header may begin with
// "solid"), scale/offset, welding, element order, and errors with file locations.
#include "geometry/stl_reader.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/primitives.h"

namespace quarry {
namespace {

std::string temp_file(const std::string& name, const std::string& content) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const char* const two_facets = R"(solid square
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 1 1 0
    endloop
  endfacet
  FACET NORMAL 0 0 1
    OUTER LOOP
      VERTEX 0 0 0
      VERTEX 1 1 0
      VERTEX +0 1e0 0
    ENDLOOP
  ENDFACET
endsolid square
)";

// The location and message of the single error a UserError carries.
Diagnostic only_error(const UserError& error) {
  EXPECT_EQ(error.diagnostics().all().size(), 1u);
  return error.diagnostics().all().front();
}

TEST(StlReader, ReadsAsciiWeldsAndAppliesScaleThenOffset) {
  const std::string path = temp_file("ascii_square.stl", two_facets);
  const Surface surface = read_stl(path, 0.001, Vec3{1, 2, 3});
  ASSERT_EQ(surface.triangle_count(), 2u);
  ASSERT_EQ(surface.vertex_count(), 4u);
  EXPECT_EQ(surface.triangles[1][0], surface.triangles[0][0]);
  EXPECT_EQ(surface.triangles[1][1], surface.triangles[0][2]);
  EXPECT_DOUBLE_EQ(surface.vertices[surface.triangles[0][1]].x, 1.001);
  EXPECT_DOUBLE_EQ(surface.vertices[surface.triangles[0][1]].y, 2.0);
  EXPECT_DOUBLE_EQ(surface.vertices[surface.triangles[0][1]].z, 3.0);
  EXPECT_NEAR(surface.triangle_areas[0] + surface.triangle_areas[1], 1e-6, 1e-18);  // (1 mm)²
  EXPECT_EQ(surface.triangle_normals[0], (Vec3{0, 0, 1}));
  EXPECT_EQ(surface.reference_vertices, surface.vertices);
  EXPECT_EQ(surface.vertex_force.size(), 4u);
  EXPECT_EQ(surface.triangle_force.size(), 2u);
}

TEST(StlReader, ReadsSeveralSolidsInOneAsciiFile) {
  // The second solid is the first one 1 m higher (its copy in the same place would be removed
  // as duplicates, DuplicateFacetsAreRemovedInEitherOrientation).
  std::string raised = two_facets;
  for (const char* level : {" 0\n", " 0\r\n"})
    for (std::size_t at = raised.find(level); at != std::string::npos; at = raised.find(level, at + 3))
      raised.replace(at, 2, " 1");
  const std::string path = temp_file("two_solids.stl", std::string(two_facets) + raised);
  EXPECT_EQ(read_stl(path, 1.0, {}).triangle_count(), 4u);
}

TEST(StlReader, BinaryRoundTripKeepsOrderAndWelding) {
  const Surface box = make_box({0, 0, 0}, {0.5, 0.25, 0.125}, 4);  // dyadic nodes: exact in float
  const std::string path = testing::TempDir() + "box.stl";
  write_stl_binary(path, box);
  EXPECT_EQ(read_bytes(path).size(), 84u + 50u * box.triangle_count());
  const Surface read = read_stl(path, 1.0, {});
  ASSERT_EQ(read.triangle_count(), box.triangle_count());
  EXPECT_EQ(read.vertex_count(), box.vertex_count());
  for (std::size_t t = 0; t < box.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(read.vertices[read.triangles[t][k]], box.vertices[box.triangles[t][k]]) << "triangle " << t;
}

TEST(StlReader, BinaryFileWhoseHeaderBeginsWithSolidIsReadAsBinary) {
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 2);
  const std::string path = testing::TempDir() + "solid_header.stl";
  write_stl_binary(path, plane);
  std::string bytes = read_bytes(path);
  std::memcpy(bytes.data(), "solid exported_by_cad", 21);
  const std::string renamed = temp_file("solid_header2.stl", bytes);
  EXPECT_EQ(read_stl(renamed, 1.0, {}).triangle_count(), 8u);
}

TEST(StlReader, LargeBinaryFileReadsAndWelds) {
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 224);  // 100,352 triangles
  const std::string path = testing::TempDir() + "large.stl";
  write_stl_binary(path, plane);
  const Surface read = read_stl(path, 1.0, {});
  EXPECT_EQ(read.triangle_count(), 100352u);
  EXPECT_EQ(read.vertex_count(), 225u * 225u);
}

// A facet whose corners lie on a line bounds nothing: it is removed and counted (the mesh's
// element ids then count the facets kept).
TEST(StlReader, DegenerateFacetIsRemovedAndCounted) {
  const std::string text =
      "solid d\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid d\n";
  std::vector<std::string> notes;
  const Surface surface = read_stl(temp_file("degenerate.stl", text), 1.0, {}, &notes);
  ASSERT_EQ(surface.triangle_count(), 1u);
  EXPECT_DOUBLE_EQ(surface.triangle_areas[0], 0.5);
  EXPECT_EQ(surface.vertex_count(), 3u);  // the point (2, 0, 0) only the degenerate facet used is gone
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("1 degenerate facet(s)"), std::string::npos) << notes[0];
}

// The same facet twice (once reversed) is one wall, not two: a sphere on a doubled plate had
// every contact counted twice (restitution 0.59 instead of 0.69). The copies are removed.
TEST(StlReader, DuplicateFacetsAreRemovedInEitherOrientation) {
  Surface square = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 2);  // 8 triangles
  const std::size_t once = square.triangle_count();
  for (std::size_t t = 0; t < once; ++t) {
    auto copy = square.triangles[t];
    if (t % 2) std::swap(copy[1], copy[2]);  // every other copy reversed
    square.triangles.push_back(copy);
  }
  square.update_normals_and_areas();
  const std::string path = testing::TempDir() + "doubled.stl";
  write_stl_binary(path, square);
  std::vector<std::string> notes;
  const Surface read = read_stl(path, 1.0, {}, &notes);
  EXPECT_EQ(read.triangle_count(), once);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("8 duplicate facet(s)"), std::string::npos) << notes[0];
}

TEST(StlReader, MeshOfOnlyDegenerateFacetsIsAUserError) {
  const std::string text =
      "solid d\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\nendloop\nendfacet\nendsolid d\n";
  EXPECT_THROW(read_stl(temp_file("only_degenerate.stl", text), 1.0, {}), UserError);
}

// An ASCII file whose solid is named in UTF-8 is not text in the 7-bit sense, and its size does
// not fit the binary layout: it is read as ASCII, not as a binary file announcing 774909216
// facets.
TEST(StlReader, AsciiWithANonAsciiNameIsReadAsAscii) {
  const std::string text = std::string("solid Ladefläche_\xc3\xa9\n") +
                           "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                           "endfacet\nendsolid\n";
  const Surface surface = read_stl(temp_file("utf8_name.stl", text), 1.0, {});
  EXPECT_EQ(surface.triangle_count(), 1u);
}

TEST(StlReader, MissingFileIsAUserError) {
  try {
    read_stl(testing::TempDir() + "does_not_exist.stl", 1.0, {});
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    EXPECT_NE(only_error(error).message.find("cannot open"), std::string::npos);
  }
}

TEST(StlReader, BadAsciiTokenReportsItsLineAndColumn) {
  std::string text = two_facets;
  text.replace(text.find("vertex 1 0 0"), 12, "vertex 1 O 0");  // letter O for zero, line 5
  const std::string path = temp_file("bad_token.stl", text);
  try {
    read_stl(path, 1.0, {});
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    const Diagnostic d = only_error(error);
    EXPECT_EQ(d.where.file, path);
    EXPECT_EQ(d.where.line, 5);
    EXPECT_EQ(d.where.column, 16);
    EXPECT_NE(d.message.find("\"O\""), std::string::npos) << d.message;
  }
}

TEST(StlReader, MissingKeywordReportsWhereItWasExpected) {
  std::string text = two_facets;
  text.replace(text.find("endloop"), 7, "endlop");  // line 7, column 5
  try {
    read_stl(temp_file("bad_keyword.stl", text), 1.0, {});
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    const Diagnostic d = only_error(error);
    EXPECT_EQ(d.where.line, 7);
    EXPECT_EQ(d.where.column, 5);
    EXPECT_NE(d.message.find("endloop"), std::string::npos);
  }
}

TEST(StlReader, TruncatedBinaryNamesTheByteOffset) {
  const Surface plane = make_plane({0, 0, 0}, {0, 0, 1}, 1.0, 2);  // 8 facets
  const std::string path = testing::TempDir() + "full.stl";
  write_stl_binary(path, plane);
  const std::string bytes = read_bytes(path).substr(0, 84 + 50 * 5 + 20);  // facet 5 cut short
  try {
    read_stl(temp_file("truncated.stl", bytes), 1.0, {});
    FAIL() << "expected UserError";
  } catch (const UserError& error) {
    const Diagnostic d = only_error(error);
    EXPECT_EQ(d.where.line, 0);
    EXPECT_NE(d.message.find("byte offset 334"), std::string::npos) << d.message;  // 84 + 50·5
  }
}

TEST(StlReader, EmptyAsciiSolidIsAUserError) {
  EXPECT_THROW(read_stl(temp_file("empty.stl", "solid nothing\nendsolid nothing\n"), 1.0, {}), UserError);
}

}  // namespace
}  // namespace quarry
