// The records of the FEM load export (issue #20): no sliver record when the run's end is not a
// multiple of the export interval, MED components named as code_aster reads them, and the
// code_aster .comm template beside the MED file naming what really is in it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "export/load_exporter.h"
#include "export/med_file.h"
#include "export/nodal_history.h"
#include "fem_export/fem_export_support.h"

namespace quarry::fem_export {
namespace {

namespace fs = std::filesystem;
using namespace quarry::fem_export_testing;

constexpr double kDt = 1e-3;       // s, time step
constexpr double kInterval = 0.1;  // s, export interval = 100 steps

// Load on vertex 0 (N, along z) in step n: -1 N in the first two intervals, -2 N in the third,
// -50 N after it (a transient, as when a run ends while something lands on the surface).
double load_in_step(int n) {
  return n <= 200 ? -1.0 : n <= 300 ? -2.0 : -50.0;
}

struct Export {
  fs::path folder;
  std::vector<std::string> notes;
};

// Drives a LoadExporter as the run loop does for `steps` steps of kDt, ending at steps·kDt.
Export run_export(const std::string& name, int steps) {
  Export result;
  result.folder = fs::path(::testing::TempDir()) / ("quarry_export_records_" + name);
  fs::remove_all(result.folder);
  std::vector<Surface> surfaces = {square_plate(0.4, 2)};
  surfaces[0].export_loads = true;
  ExportSpec spec;
  spec.enabled = true;
  spec.interval = kInterval;
  spec.formats = {Located<ExportFormat>(ExportFormat::med)};
  const std::vector<const Surface*> meshes = {&surfaces[0]};
  LoadExporter exporter(spec, meshes, result.folder, kDt, kDt * steps, std::nullopt);
  for (int n = 1; n <= steps; ++n) {
    surfaces[0].vertex_force[0] = {0.0, 0.0, load_in_step(n)};
    surfaces[0].triangle_force[0] = {0.0, 0.0, load_in_step(n)};
    surfaces[0].mark_step_loads();
    exporter.after_step(meshes, kDt * n, static_cast<std::uint64_t>(n), kDt);
  }
  exporter.finish(meshes, kDt * steps, false);
  result.notes = exporter.notes();
  return result;
}

bool any_note_contains(const Export& e, const std::string& text) {
  for (const std::string& note : e.notes)
    if (note.find(text) != std::string::npos) return true;
  return false;
}

// End 0.303 s: before issue #20 the records were 0.1, 0.2, 0.3 and a 3-step sliver at 0.303 s
// whose mean was the transient's -50 N. Now the remainder (3 steps < half an interval) joins
// the third interval: its record covers 0.2–0.303 s, mean (100·(−2) + 3·(−50)) / 103 N.
TEST(ExportRecords, RemainderShorterThanHalfAnIntervalJoinsTheLastRecord) {
  const Export e = run_export("merged", 303);
  const MedLoadFile med = read_med_loads((e.folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 3u);
  EXPECT_NEAR(med.frames[0].time, 0.1, 1e-12);
  EXPECT_NEAR(med.frames[1].time, 0.2, 1e-12);
  EXPECT_NEAR(med.frames[2].time, 0.303, 1e-12);
  EXPECT_NEAR(med.frames[1].nodal_force[0].z, -1.0, 1e-12);
  EXPECT_NEAR(med.frames[2].nodal_force[0].z, (100.0 * -2.0 + 3.0 * -50.0) / 103.0, 1e-12);
  NodalHistoryReader history(e.folder / "fem_export" / "plate_nodal_forces.bin");
  EXPECT_EQ(history.frame_count(), 3u);
  EXPECT_TRUE(any_note_contains(e, "the remainder up to the end joined it"));
}

// End 0.36 s: a remainder of 60 steps (≥ half an interval) is a record of its own, 0.3–0.36 s,
// and the run's notes flag its length.
TEST(ExportRecords, RemainderOfAtLeastHalfAnIntervalIsItsOwnFlaggedRecord) {
  const Export e = run_export("own", 360);
  const MedLoadFile med = read_med_loads((e.folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 4u);
  EXPECT_NEAR(med.frames[2].time, 0.3, 1e-12);
  EXPECT_NEAR(med.frames[2].nodal_force[0].z, -2.0, 1e-12);
  EXPECT_NEAR(med.frames[3].time, 0.36, 1e-12);
  EXPECT_NEAR(med.frames[3].nodal_force[0].z, -50.0, 1e-12);
  EXPECT_TRUE(
      any_note_contains(e, "over 0.06 s, not one interval of 0.1 s (the run ended inside it)"));
}

// An end on an interval boundary gives whole intervals and no note.
TEST(ExportRecords, WholeIntervalsAreUnchanged) {
  const Export e = run_export("whole", 300);
  const MedLoadFile med = read_med_loads((e.folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 3u);
  EXPECT_NEAR(med.frames[2].time, 0.3, 1e-12);
  EXPECT_FALSE(any_note_contains(e, "last export record"));
}

// The texts between quotes after each occurrence of `key` (e.g. NOM_MED=') in `text`.
std::vector<std::string> quoted_after(const std::string& text, const std::string& key) {
  std::vector<std::string> values;
  for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const std::size_t begin = at + key.size();
    values.push_back(text.substr(begin, text.find('\'', begin) - begin));
  }
  return values;
}

// MED components carry code_aster's names (PRES; FX FY FZ) and the .comm template reads the MED
// file's real mesh and fields at the real record instants.
TEST(ExportRecords, MedComponentsAndAsterCommandFileMatchTheMedFile) {
  const Export e = run_export("comm", 303);
  const MedLoadFile med = read_med_loads((e.folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.field_names.size(), med.field_components.size());
  for (std::size_t f = 0; f < med.field_names.size(); ++f) {
    const std::vector<std::string> expected = med.field_names[f] == kMedPressureField
                                                  ? std::vector<std::string>{"PRES"}
                                                  : std::vector<std::string>{"FX", "FY", "FZ"};
    EXPECT_EQ(med.field_components[f], expected) << med.field_names[f];
  }
  const std::string comm = read_text(e.folder / "fem_export" / "plate.comm");
  ASSERT_FALSE(comm.empty());
  EXPECT_NE(comm.find("F mmed plate.med D 20"), std::string::npos);
  EXPECT_NE(comm.find("DEBUT("), std::string::npos);
  EXPECT_NE(comm.find("FIN()"), std::string::npos);
  // NOM_MED of LIRE_MAILLAGE is the mesh; those of LIRE_CHAMP are fields of the file.
  const std::vector<std::string> names = quoted_after(comm, "NOM_MED='");
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], med.mesh_name);
  for (std::size_t k = 1; k < names.size(); ++k)
    EXPECT_NE(std::find(med.field_names.begin(), med.field_names.end(), names[k]),
              med.field_names.end())
        << names[k];
  EXPECT_EQ(quoted_after(comm, "TYPE_CHAM='"),
            (std::vector<std::string>{"NOEU_FORC_R", "ELEM_PRES_R"}));
  // The instant list is the MED steps' times, in order, to the last digit.
  const std::size_t open = comm.find("instants = [");
  ASSERT_NE(open, std::string::npos);
  const char* cursor = comm.c_str() + open + 12;
  std::vector<double> instants;
  while (*cursor != ']') {
    char* end = nullptr;
    instants.push_back(std::strtod(cursor, &end));
    ASSERT_NE(end, cursor);
    cursor = end;
    while (*cursor == ',' || *cursor == ' ') ++cursor;
  }
  ASSERT_EQ(instants.size(), med.frames.size());
  for (std::size_t k = 0; k < instants.size(); ++k) EXPECT_EQ(instants[k], med.frames[k].time) << k;
}

// A moving surface (a prescribed motion or a coupling partner's, Surface::moving): each record
// also carries the mean displacement of the vertices from the mesh written (their reference
// positions) over the record's steps, by the loads' rectangle rule, as the MED node field
// `displacement` (DX DY DZ, read by the .comm as NOEU_DEPL_R) and a VTU point array. The plate
// translates at v = (0.2, 0, −0.5) m/s: u(t_n) = v t_n at t_n = n dt, so the mean over the steps
// n = a+1 … b of a record is v dt (a + b + 1)/2 = v (t_start + t_end + dt)/2 exactly. A fixed
// surface gets no displacement field.
TEST(ExportRecords, MovingSurfaceRecordsItsMeanDisplacement) {
  const fs::path folder = fs::path(::testing::TempDir()) / "quarry_export_records_moving";
  fs::remove_all(folder);
  std::vector<Surface> surfaces = {square_plate(0.4, 2)};
  surfaces[0].export_loads = true;
  surfaces[0].moving = true;
  ExportSpec spec;
  spec.enabled = true;
  spec.interval = kInterval;
  spec.formats = {Located<ExportFormat>(ExportFormat::med), Located<ExportFormat>(ExportFormat::vtu)};
  const std::vector<const Surface*> meshes = {&surfaces[0]};
  const Vec3 velocity{0.2, 0.0, -0.5};  // m/s
  const int steps = 250;                // records at 0.1, 0.2 and 0.25 s (a remainder of half an interval)
  LoadExporter exporter(spec, meshes, folder, kDt, kDt * steps, std::nullopt);
  for (int n = 1; n <= steps; ++n) {
    for (std::size_t v = 0; v < surfaces[0].vertex_count(); ++v)
      surfaces[0].vertices[v] = surfaces[0].reference_vertices[v] + velocity * (kDt * n);
    surfaces[0].update_normals_and_areas();
    surfaces[0].vertex_force[0] = {0.0, 0.0, -1.0};
    surfaces[0].mark_step_loads();
    exporter.after_step(meshes, kDt * n, static_cast<std::uint64_t>(n), kDt);
  }
  exporter.finish(meshes, kDt * steps, false);

  const MedLoadFile med = read_med_loads((folder / "fem_export" / "plate.med").string());
  ASSERT_EQ(med.frames.size(), 3u);
  ASSERT_EQ(med.displacements.size(), 3u);
  EXPECT_EQ(med.nodes, surfaces[0].reference_vertices);  // the mesh is the reference one
  const auto field = std::find(med.field_names.begin(), med.field_names.end(), kMedDisplacementField);
  ASSERT_NE(field, med.field_names.end());
  const auto f = static_cast<std::size_t>(field - med.field_names.begin());
  EXPECT_EQ(med.field_components[f], (std::vector<std::string>{"DX", "DY", "DZ"}));
  EXPECT_EQ(med.field_units[f], "m");
  const double starts[3] = {0.0, 0.1, 0.2};
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3 expected = velocity * (0.5 * (starts[k] + med.frames[k].time + kDt));  // m
    ASSERT_EQ(med.displacements[k].size(), surfaces[0].vertex_count());
    for (const Vec3& u : med.displacements[k]) {
      EXPECT_NEAR(u.x, expected.x, 1e-15) << "record " << k;
      EXPECT_NEAR(u.y, expected.y, 1e-15) << "record " << k;
      EXPECT_NEAR(u.z, expected.z, 1e-15) << "record " << k;
    }
  }
  const std::string vtu = read_text(folder / "fem_export" / "plate_loads_000002.vtu");
  EXPECT_NE(vtu.find("Name=\"displacement\""), std::string::npos);
  const std::string comm = read_text(folder / "fem_export" / "plate.comm");
  EXPECT_EQ(quoted_after(comm, "TYPE_CHAM='"),
            (std::vector<std::string>{"NOEU_FORC_R", "ELEM_PRES_R", "NOEU_DEPL_R"}));
  const std::vector<std::string> names = quoted_after(comm, "NOM_MED='");
  EXPECT_NE(std::find(names.begin(), names.end(), std::string(kMedDisplacementField)), names.end());

  // The same run of a fixed plate: no displacement field, nothing about it in the .comm.
  const Export fixed = run_export("fixed_has_no_displacement", 200);
  const MedLoadFile fixed_med = read_med_loads((fixed.folder / "fem_export" / "plate.med").string());
  EXPECT_TRUE(fixed_med.displacements.empty());
  EXPECT_EQ(std::count(fixed_med.field_names.begin(), fixed_med.field_names.end(), kMedDisplacementField), 0);
  EXPECT_EQ(read_text(fixed.folder / "fem_export" / "plate.comm").find("DEPL"), std::string::npos);
}

}  // namespace
}  // namespace quarry::fem_export
