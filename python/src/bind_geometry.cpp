// Meshes, point clouds and the skeleton stage.
#include <pybind11/stl.h>

#include <filesystem>

#include "bindings.h"
#include "convert.h"
#include "skelgrasp/datasets/input.h"
#include "skelgrasp/skeleton/extraction.h"
#include "skelgrasp/skeleton/output.h"

namespace skelgrasp::python {
namespace {

Mesh makeMesh(const py::object& vertices, const py::object& faces, const std::string& name) {
  Mesh m;
  m.mesh.vertices = toPoints(vertices, "vertices");
  m.mesh.faces = toFaces(faces, m.mesh.vertices.size(), "faces");
  if (m.mesh.vertices.empty()) throw InvalidArgument("vertices: the mesh has no vertices");
  if (m.mesh.faces.empty()) throw InvalidArgument("faces: the mesh has no faces");
  m.name = name;
  return m;
}

Mesh loadMeshFile(const std::string& path, const std::string& units) {
  MeshLoadOptions options;
  options.units = parseLengthUnit(units);
  Mesh m;
  py::gil_scoped_release release;
  m.mesh = loadMesh(path, options, &m.info);
  m.name = std::filesystem::path(path).filename().string();
  return m;
}

Cloud makeCloud(const py::object& points, const py::object& normals, const py::object& colors,
                const std::string& name) {
  Cloud c;
  c.scan.cloud.points = toPoints(points, "points");
  if (c.scan.cloud.points.empty()) throw InvalidArgument("points: the cloud has no points");
  if (!normals.is_none()) {
    c.scan.cloud.normals = toPoints(normals, "normals");
    if (c.scan.cloud.normals.size() != c.scan.cloud.points.size())
      throw InvalidArgument("normals: " + std::to_string(c.scan.cloud.normals.size()) +
                            " rows for " + std::to_string(c.scan.cloud.points.size()) +
                            " points (one normal per point)");
    for (auto& n : c.scan.cloud.normals) {
      if (n.norm() == 0) throw InvalidArgument("normals: a normal has length 0");
      n.normalize();
    }
  }
  if (!colors.is_none()) c.scan.cloud.colors = toColours(colors, c.scan.cloud.size(), "colors");
  c.scan.source = name;
  return c;
}

Cloud loadCloudFile(const std::string& path, const std::string& units) {
  datasets::InputOptions options;
  options.units.units = parseLengthUnit(units);
  Cloud c;
  py::gil_scoped_release release;
  c.scan = datasets::loadInput(path, options);
  return c;
}

SkeletonOutput runSkeleton(const Mesh& mesh, const std::string& regularisation,
                           double alpha_divisor, double offset_divisor, double remesh_target_edge_m,
                           std::optional<std::size_t> max_vertices, double spur_radius_factor,
                           double curvature_stencil_m) {
  skeleton::SkeletonParams params;
  params.regularisation.method = geometry::parseRegularisationMethod(regularisation);
  params.regularisation.alpha_divisor = alpha_divisor;
  params.regularisation.offset_divisor = offset_divisor;
  params.regularisation.remesh_target_edge_m = remesh_target_edge_m;
  params.regularisation.max_vertices = max_vertices;
  params.spur_radius_factor = spur_radius_factor;
  params.graph.curvature_stencil_m = curvature_stencil_m;
  SkeletonOutput out{{}, mesh};
  py::gil_scoped_release release;
  out.result = skeleton::extractSkeleton(mesh.mesh, params);
  return out;
}

}  // namespace

void bindGeometry(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", R"doc(
A triangle mesh in metres: ``vertices`` (N x 3 float64) and ``faces`` (F x 3 int, counter-clockwise
seen from outside). Made from numpy arrays or by :func:`load_mesh`.

Raises ValueError for another shape, a non-finite coordinate, an index outside the vertices or an
empty mesh.)doc")
      .def(py::init(&makeMesh), py::arg("vertices"), py::arg("faces"), py::arg("name") = "mesh",
           "Mesh(vertices, faces, name='mesh'): the arrays are copied; ``name`` is the object's "
           "name in to_dict() outputs.")
      .def_property_readonly(
          "vertices", [](const Mesh& self) { return fromPoints(self.mesh.vertices); },
          "N x 3 float64 vertex positions (metres; a copy).")
      .def_property_readonly(
          "faces", [](const Mesh& self) { return fromFaces(self.mesh.faces); },
          "F x 3 int64 vertex indices (a copy).")
      .def_readonly("name", &Mesh::name, "File name, or the name given to Mesh().")
      .def_property_readonly(
          "path", [](const Mesh& self) { return self.info.path; },
          "The file it was loaded from ('' for a mesh made from arrays).")
      .def_property_readonly(
          "scale_to_meters", [](const Mesh& self) { return self.info.scale_to_meters; },
          "Factor applied to the file's coordinates (1000 mm -> m is 0.001).")
      .def_property_readonly(
          "bounds",
          [](const Mesh& self) {
            const auto box = self.mesh.bounds();
            return fromPoints({box.min, box.max});
          },
          "2 x 3 array: the axis-aligned bounding box's min and max corners.")
      .def_property_readonly(
          "area", [](const Mesh& self) { return self.mesh.area(); }, "Surface area in m^2.")
      .def_property_readonly(
          "volume", [](const Mesh& self) { return self.mesh.signedVolume(); },
          "Signed enclosed volume in m^3 (positive for a closed outward-oriented mesh).")
      .def("__repr__", [](const Mesh& self) {
        return "<skelgrasp.Mesh '" + self.name + "': " + std::to_string(self.mesh.numVertices()) +
               " vertices, " + std::to_string(self.mesh.numFaces()) + " faces>";
      });

  m.def("load_mesh", &loadMeshFile, py::arg("path"), py::arg("units") = "auto", R"doc(
Loads a mesh file (PLY, OBJ, OFF, STL) in metres. ``units``: 'auto' (a bounding-box diagonal
above 5 means millimetres, scaled with a warning), 'm' or 'mm'.

Raises FileNotFoundError for a missing file and OSError for an unreadable or malformed one, with
the message the command line prints ("<path>: <problem>").)doc");

  py::class_<Cloud>(m, "PointCloud", R"doc(
A point cloud in metres: ``points`` (N x 3 float64), optional unit ``normals`` (N x 3) and
``colors`` (N x 3, 0-255). Made from numpy arrays or by :func:`load_cloud`; the input of
:func:`reconstruct` and :func:`run`.)doc")
      .def(py::init(&makeCloud), py::arg("points"), py::arg("normals") = py::none(),
           py::arg("colors") = py::none(), py::arg("name") = "cloud",
           "PointCloud(points, normals=None, colors=None, name='cloud'); the arrays are copied.")
      .def_property_readonly(
          "points", [](const Cloud& self) { return fromPoints(self.scan.cloud.points); },
          "N x 3 float64 points (metres; a copy). Organised clouds keep NaN rows for pixels "
          "without depth.")
      .def_property_readonly(
          "normals",
          [](const Cloud& self) -> py::object {
            if (!self.scan.cloud.hasNormals()) return py::none();
            return fromPoints(self.scan.cloud.normals);
          },
          "N x 3 unit normals, or None.")
      .def_property_readonly(
          "colors",
          [](const Cloud& self) -> py::object {
            if (!self.scan.cloud.hasColors()) return py::none();
            py::array_t<std::uint8_t> out(
                {static_cast<py::ssize_t>(self.scan.cloud.size()), py::ssize_t{3}});
            auto view = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < self.scan.cloud.size(); ++i)
              for (int c = 0; c < 3; ++c)
                view(static_cast<py::ssize_t>(i), c) =
                    self.scan.cloud.colors[i][static_cast<std::size_t>(c)];
            return out;
          },
          "N x 3 uint8 colours, or None.")
      .def_property_readonly(
          "sensor_origin",
          [](const Cloud& self) { return fromPoints({self.scan.cloud.sensor_origin}); },
          "1 x 3: where the sensor was (PCD VIEWPOINT or capture pose; 0 when unknown).")
      .def_property_readonly(
          "source", [](const Cloud& self) { return self.scan.source; },
          "File or folder it came from (or the name given).")
      .def("__len__", [](const Cloud& self) { return self.scan.cloud.size(); })
      .def("__repr__", [](const Cloud& self) {
        return "<skelgrasp.PointCloud '" + self.scan.source +
               "': " + std::to_string(self.scan.cloud.size()) + " points>";
      });

  m.def("load_cloud", &loadCloudFile, py::arg("path"), py::arg("units") = "auto", R"doc(
Loads what ``skelgrasp run INPUT`` reads: a PCD/PLY cloud, a capture description (.json: depth
image, mask, intrinsics, camera pose) or a YCB raw capture folder. ``units``: 'auto', 'm', 'mm'.

Raises FileNotFoundError / OSError with the command line's message.)doc");

  py::class_<SkeletonOutput>(m, "Skeleton", R"doc(
The mean-curvature-flow skeleton of a mesh (paper Sec. III), from :func:`skeleton`.)doc")
      .def_property_readonly(
          "ok", [](const SkeletonOutput& s) { return s.result.status.ok(); },
          "True when the stage succeeded (else see ``status``).")
      .def_property_readonly(
          "status",
          [](const SkeletonOutput& s) {
            return py::make_tuple(toString(s.result.status.code), s.result.status.message);
          },
          "(code, message): 'ok', 'invalid_input', 'no_result', ...")
      .def_property_readonly(
          "vertices",
          [](const SkeletonOutput& s) {
            std::vector<Eigen::Vector3d> p;
            for (const auto& v : s.result.skeleton.vertices) p.push_back(v.position);
            return fromPoints(p);
          },
          "N x 3 float64 skeleton vertex positions (metres).")
      .def_property_readonly(
          "edges",
          [](const SkeletonOutput& s) {
            IndexMatrix out(
                {static_cast<py::ssize_t>(s.result.skeleton.edges.size()), py::ssize_t{2}});
            auto view = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < s.result.skeleton.edges.size(); ++i)
              for (int c = 0; c < 2; ++c)
                view(static_cast<py::ssize_t>(i), c) = s.result.skeleton.edges[i][c];
            return out;
          },
          "E x 2 int64 vertex index pairs.")
      .def_property_readonly(
          "types",
          [](const SkeletonOutput& s) {
            std::vector<std::string> t;
            for (const auto& v : s.result.skeleton.vertices) t.push_back(toString(v.type));
            return t;
          },
          "Per vertex: 'branch' (degree > 2), 'endpoint' (degree <= 1) or 'connecting'.")
      .def_property_readonly(
          "segments", [](const SkeletonOutput& s) { return fromJson(s.json()["segments"]); },
          "List of dicts {id, vertices, length, ends, end_vertices} (skeleton.json's segments).")
      .def_property_readonly(
          "surface_points",
          [](const SkeletonOutput& s) {
            py::list out;
            for (const auto& v : s.result.skeleton.vertices)
              out.append(py::array_t<std::int64_t>(
                  static_cast<py::ssize_t>(v.surface_points.size()),
                  std::vector<std::int64_t>(v.surface_points.begin(), v.surface_points.end())
                      .data()));
            return out;
          },
          "Per skeleton vertex: int64 array of the input mesh's vertex indices mapped to it "
          "(every input vertex in exactly one).")
      .def_property_readonly(
          "regularised_mesh",
          [](const SkeletonOutput& s) {
            return Mesh{s.result.regularised_mesh, {}, s.input.name + " (regularised)"};
          },
          "The closed mesh that was contracted.")
      .def(
          "to_dict", [](const SkeletonOutput& s) { return fromJson(s.json()); },
          "The skeleton.json document (schema skelgrasp.skeleton/1, docs/skeleton.md).")
      .def("__repr__", [](const SkeletonOutput& s) {
        return "<skelgrasp.Skeleton: " + skeleton::summaryLine(s.result, s.input.name) + ">";
      });

  const skeleton::SkeletonParams defaults;
  m.def("skeleton", &runSkeleton, py::arg("mesh"), py::kw_only(),
        py::arg("regularisation") = std::string(toString(defaults.regularisation.method)),
        py::arg("alpha_divisor") = defaults.regularisation.alpha_divisor,
        py::arg("offset_divisor") = defaults.regularisation.offset_divisor,
        py::arg("remesh_target_edge_m") = defaults.regularisation.remesh_target_edge_m,
        py::arg("max_vertices") = defaults.regularisation.max_vertices,
        py::arg("spur_radius_factor") = defaults.spur_radius_factor,
        py::arg("curvature_stencil_m") = defaults.graph.curvature_stencil_m,
        R"doc(
Skeleton of a mesh: regularisation to a closed 2-manifold ('alpha_wrap', 'auto' or 'none'),
mean-curvature-flow contraction, vertex classes and segments (``skelgrasp skeleton``; parameters
as skeleton::SkeletonParams, docs/skeleton.md). ``max_vertices``: simplify a larger closed mesh by
edge collapse to about this many vertices before the contraction (None: never; at least 4). A mesh the stage cannot process gives a result
whose ``ok`` is False, with the reason in ``status``.)doc");
}

}  // namespace skelgrasp::python
