// Crest lines with CGAL (Monge_via_jet_fitting + Ridges_3), timed per stage, for the
// side-by-side benchmark against `crestline extract` (issue #9; see run.sh next to this file).
//
// Pipeline, one stage per timer:
//   load     read the file as a polygon soup (OFF, OBJ or PLY as CGAL reads them), split polygons
//            into fans, drop faces that repeat a vertex, drop unreferenced vertices (Ridges_3
//            crashes on them), orient the soup if it is not already a polygon mesh, build a
//            Surface_mesh.
//   monge    per vertex: area-weighted normal, the vertex plus its 2-ring (grown ring by ring while
//            fewer than the 10 points a degree-3 jet needs), degree-3 jet and degree-3 Monge form,
//            oriented along the normal; k1 k2 b0 b3 d1 d2 stored in property maps.
//   ridges   CGAL::compute_crest_ridges with Ridge_order_3 (umbilics are not computed).
//   output   OBJ polylines (`v` and `l` records), line count and total length.
//
// Usage: ridges_cgal MESH [-o OUT.obj]
// Prints one JSON object on stdout.

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Ridges.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;
using HalfedgeIndex = Mesh::Halfedge_index;
using ScalarMap = Mesh::Property_map<VertexIndex, double>;
using VectorMap = Mesh::Property_map<VertexIndex, Vector>;
using Fitter = CGAL::Monge_via_jet_fitting<Kernel>;
using Ridges = CGAL::Ridge_approximation<Mesh, ScalarMap, VectorMap>;
using RidgeLine = CGAL::Ridge_line<Mesh>;

constexpr std::size_t kJetDegree = 3;
constexpr std::size_t kMongeDegree = 3;
constexpr std::size_t kRings = 2;
// A degree-d jet has (d + 1)(d + 2) / 2 coefficients; the least-squares fit needs as many points.
constexpr std::size_t kMinPoints = (kJetDegree + 1) * (kJetDegree + 2) / 2;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "error: " << message << "\n";
  std::exit(1);
}

struct Loaded {
  Mesh mesh;
  std::size_t soup_vertices = 0;
  std::size_t soup_faces = 0;
  std::size_t dropped_faces = 0;
  std::size_t unreferenced_vertices = 0;
  bool reoriented = false;
};

// Reads `path` into a Surface_mesh of triangles with every vertex referenced.
Loaded load_mesh(const std::string& path) {
  Loaded out;
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_polygon_soup(path, points, polygons)) {
    fail("CGAL could not read " + path + " (OFF, OBJ and PLY without triangle strips are supported)");
  }
  out.soup_vertices = points.size();
  out.soup_faces = polygons.size();

  std::vector<std::array<std::size_t, 3>> triangles;
  triangles.reserve(polygons.size());
  for (const auto& polygon : polygons) {
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
      std::array<std::size_t, 3> t{polygon[0], polygon[i], polygon[i + 1]};
      bool bad = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
      for (std::size_t v : t) bad = bad || v >= points.size();
      if (bad) {
        ++out.dropped_faces;
      } else {
        triangles.push_back(t);
      }
    }
  }
  polygons.clear();
  polygons.shrink_to_fit();

  // Renumber the referenced vertices in their input order.
  constexpr std::size_t kUnused = static_cast<std::size_t>(-1);
  std::vector<std::size_t> new_index(points.size(), kUnused);
  std::vector<Point> kept;
  kept.reserve(points.size());
  for (auto& t : triangles) {
    for (std::size_t& v : t) {
      if (new_index[v] == kUnused) {
        new_index[v] = kept.size();
        kept.push_back(points[v]);
      }
      v = new_index[v];
    }
  }
  out.unreferenced_vertices = points.size() - kept.size();
  points.clear();
  points.shrink_to_fit();

  namespace PMP = CGAL::Polygon_mesh_processing;
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles)) {
    // Non-manifold or inconsistently oriented: CGAL duplicates the offending vertices.
    out.reoriented = true;
    PMP::orient_polygon_soup(kept, triangles);
  }
  PMP::polygon_soup_to_polygon_mesh(kept, triangles, out.mesh);
  return out;
}

// Area-weighted vertex normal (the sum of the incident faces' cross products).
Vector vertex_normal(const Mesh& mesh, VertexIndex v) {
  Vector n(0.0, 0.0, 0.0);
  for (HalfedgeIndex h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
    if (mesh.is_border(h)) continue;
    const Point& a = mesh.point(mesh.source(h));
    const Point& b = mesh.point(mesh.target(h));
    const Point& c = mesh.point(mesh.target(mesh.next(h)));
    n = n + CGAL::cross_product(b - a, c - a);
  }
  return n;
}

// The vertex first (Monge_via_jet_fitting takes the first point as the origin of its fit), then
// its rings: at least `kRings` of them and more while fewer than `kMinPoints` points are found.
// `stamp` marks the vertices already taken for the current centre.
void gather_neighbourhood(const Mesh& mesh, VertexIndex v, std::vector<unsigned>& stamp,
                          std::vector<VertexIndex>& ring, std::vector<VertexIndex>& next,
                          std::vector<Point>& points) {
  const unsigned mark = static_cast<unsigned>(v) + 1;
  points.clear();
  ring.clear();
  ring.push_back(v);
  stamp[v] = mark;
  points.push_back(mesh.point(v));
  for (std::size_t depth = 0; !ring.empty(); ++depth) {
    if (depth >= kRings && points.size() >= kMinPoints) break;
    next.clear();
    for (VertexIndex u : ring) {
      for (VertexIndex w : CGAL::vertices_around_target(mesh.halfedge(u), mesh)) {
        if (stamp[w] == mark) continue;
        stamp[w] = mark;
        next.push_back(w);
        points.push_back(mesh.point(w));
      }
    }
    ring.swap(next);
  }
}

struct Fields {
  ScalarMap k1, k2, b0, b3, p1, p2;
  VectorMap d1, d2;
  std::size_t skipped = 0;  // vertices whose component has fewer than kMinPoints vertices
};

Fields fit_monge_forms(Mesh& mesh) {
  Fields f;
  f.k1 = mesh.add_property_map<VertexIndex, double>("v:k1", 0.0).first;
  f.k2 = mesh.add_property_map<VertexIndex, double>("v:k2", 0.0).first;
  f.b0 = mesh.add_property_map<VertexIndex, double>("v:b0", 0.0).first;
  f.b3 = mesh.add_property_map<VertexIndex, double>("v:b3", 0.0).first;
  // P1 and P2 are only read with Ridge_order_4; Ridge_approximation still takes them.
  f.p1 = mesh.add_property_map<VertexIndex, double>("v:p1", 0.0).first;
  f.p2 = mesh.add_property_map<VertexIndex, double>("v:p2", 0.0).first;
  const Vector zero(0.0, 0.0, 0.0);
  f.d1 = mesh.add_property_map<VertexIndex, Vector>("v:d1", zero).first;
  f.d2 = mesh.add_property_map<VertexIndex, Vector>("v:d2", zero).first;

  std::vector<unsigned> stamp(mesh.number_of_vertices(), 0);
  std::vector<VertexIndex> ring, next;
  std::vector<Point> points;
  Fitter fitter;
  for (VertexIndex v : mesh.vertices()) {
    gather_neighbourhood(mesh, v, stamp, ring, next, points);
    if (points.size() < kMinPoints) {
      ++f.skipped;
      continue;
    }
    Fitter::Monge_form form = fitter(points.begin(), points.end(), kJetDegree, kMongeDegree);
    form.comply_wrt_given_normal(vertex_normal(mesh, v));
    f.k1[v] = form.principal_curvatures(0);
    f.k2[v] = form.principal_curvatures(1);
    f.b0[v] = form.third_order_coefficients(0);
    f.b3[v] = form.third_order_coefficients(3);
    f.d1[v] = form.maximal_principal_direction();
    f.d2[v] = form.minimal_principal_direction();
  }
  return f;
}

struct Written {
  std::size_t lines = 0;
  std::size_t points = 0;
  std::size_t max_crest = 0;
  std::size_t min_crest = 0;
  double length = 0.0;
};

// Writes the lines as OBJ polylines (when `path` is not empty) and measures them.
Written write_lines(const Mesh& mesh, const std::vector<RidgeLine*>& lines, const std::string& path) {
  Written w;
  std::ofstream file;
  std::vector<char> buffer(1 << 20);
  if (!path.empty()) {
    file.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    file.open(path);
    if (!file) fail("cannot write " + path);
    file.precision(17);
  }
  std::size_t next_vertex = 1;
  std::string record;
  for (const RidgeLine* line : lines) {
    const auto* crossings = line->line();
    if (crossings->empty()) continue;
    ++w.lines;
    if (line->line_type() == CGAL::MAX_CREST_RIDGE) ++w.max_crest;
    if (line->line_type() == CGAL::MIN_CREST_RIDGE) ++w.min_crest;
    bool first = true;
    Point previous;
    for (const auto& [h, t] : *crossings) {
      // The crossing divides the halfedge p -> q with weight t on p (as Ridge_line::dump_4ogl).
      const Point& p = mesh.point(mesh.source(h));
      const Point& q = mesh.point(mesh.target(h));
      const Point r = CGAL::barycenter(p, t, q);
      if (!first) w.length += std::sqrt(CGAL::squared_distance(previous, r));
      previous = r;
      first = false;
      if (file.is_open()) file << "v " << r.x() << ' ' << r.y() << ' ' << r.z() << '\n';
    }
    if (file.is_open()) {
      file << 'l';
      for (std::size_t i = 0; i < crossings->size(); ++i) file << ' ' << next_vertex + i;
      file << '\n';
    }
    next_vertex += crossings->size();
    w.points += crossings->size();
  }
  if (file.is_open()) {
    file.flush();
    if (!file) fail("cannot write " + path);
  }
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, output;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-o" && i + 1 < argc) {
      output = argv[++i];
    } else if (a == "-h" || a == "--help") {
      std::cout << "usage: ridges_cgal MESH [-o OUT.obj]\n";
      return 0;
    } else if (input.empty() && !a.empty() && a[0] != '-') {
      input = a;
    } else {
      fail("unexpected argument '" + a + "' (usage: ridges_cgal MESH [-o OUT.obj])");
    }
  }
  if (input.empty()) fail("no mesh given (usage: ridges_cgal MESH [-o OUT.obj])");

  const auto start = Clock::now();
  auto t = Clock::now();
  Loaded loaded = load_mesh(input);
  Mesh& mesh = loaded.mesh;
  const double load_s = seconds_since(t);
  if (mesh.number_of_faces() == 0) fail(input + " has no usable triangle");

  t = Clock::now();
  Fields f = fit_monge_forms(mesh);
  const double monge_s = seconds_since(t);

  t = Clock::now();
  std::vector<RidgeLine*> lines;
  CGAL::compute_crest_ridges(mesh, f.k1, f.k2, f.b0, f.b3, f.d1, f.d2, f.p1, f.p2,
                             std::back_inserter(lines), CGAL::Ridge_order_3);
  const double ridges_s = seconds_since(t);

  t = Clock::now();
  Written w = write_lines(mesh, lines, output);
  for (RidgeLine* line : lines) delete line;
  const double output_s = seconds_since(t);
  const double total_s = seconds_since(start);

  CGAL::Bbox_3 box;
  for (VertexIndex v : mesh.vertices()) box += mesh.point(v).bbox();
  const double dx = box.xmax() - box.xmin(), dy = box.ymax() - box.ymin(), dz = box.zmax() - box.zmin();
  const double diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);

  std::printf(
      "{\"input\": \"%s\", \"vertices\": %zu, \"faces\": %zu, \"soup_vertices\": %zu, "
      "\"soup_polygons\": %zu, \"dropped_faces\": %zu, \"unreferenced_vertices\": %zu, "
      "\"reoriented\": %s, \"skipped_vertices\": %zu, "
      "\"seconds\": {\"load\": %.6f, \"monge\": %.6f, \"ridges\": %.6f, \"output\": %.6f, "
      "\"total\": %.6f}, "
      "\"lines\": %zu, \"max_crest_lines\": %zu, \"min_crest_lines\": %zu, \"points\": %zu, "
      "\"length\": %.9g, \"bbox_diagonal\": %.9g}\n",
      input.c_str(), static_cast<std::size_t>(mesh.number_of_vertices()),
      static_cast<std::size_t>(mesh.number_of_faces()), loaded.soup_vertices, loaded.soup_faces,
      loaded.dropped_faces, loaded.unreferenced_vertices, loaded.reoriented ? "true" : "false",
      f.skipped, load_s, monge_s, ridges_s, output_s, total_s, w.lines, w.max_crest, w.min_crest,
      w.points, w.length, diagonal);
  return 0;
}
