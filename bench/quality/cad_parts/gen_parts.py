#!/usr/bin/env python3
"""CAD parts beyond ../shared/quality/cad, for score_cad.py --cases OUTDIR and the test suite.

usage: python bench/quality/cad_parts/gen_parts.py [OUTDIR] [--only NAME]   (default OUTDIR: cad_parts/)
needs: pip install cadquery-ocp gmsh numpy   (tested with cadquery-ocp 8.0.1.1.0, gmsh 4.15.2)
The export meshes of crates/crestline/tests/data/cad were made by it (2026-11-26).

For every part: a B-rep built with OpenCASCADE (OCP), then
  <part>-export.obj/.fea   BRepMesh_IncrementalMesh, linear deflection 5e-4 * diagonal (absolute),
                           angular deflection 0.5 rad: fans of long thin triangles on planar faces
  <part>-uniform.obj/.fea  gmsh (OCC kernel, same B-rep written as .brep), Frontal-Delaunay,
                           mesh size 1% of the diagonal
.fea: the count, then mesh edges 'i j' (0-based) that lie on a B-rep edge whose two faces'
outward normals differ by more than 1 degree somewhere along the edge (sampled at 21 points).
Seams and degenerate edges are never sharp; fillet boundaries are tangent, so not sharp.
"""
import math
import sys
from pathlib import Path

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                BRepBuilderAPI_MakePolygon, BRepBuilderAPI_MakeVertex,
                                BRepBuilderAPI_MakeWire, BRepBuilderAPI_Transform)
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer, BRepFilletAPI_MakeFillet
from OCP.BRepGProp import BRepGProp_Face
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepPrimAPI import (BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCone, BRepPrimAPI_MakeCylinder,
                             BRepPrimAPI_MakePrism, BRepPrimAPI_MakeRevol, BRepPrimAPI_MakeSphere)
from OCP.BRepTools import BRepTools
from OCP.Bnd import Bnd_Box
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.gp import gp_Ax1, gp_Ax2, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec, gp_Pnt2d
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS
from OCP.OCP.collections import (IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as TopTools_IndexedDataMapOfShapeListOfShape,
                                IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as TopTools_IndexedMapOfShape)

SHARP_DEG = 1.0


# ---------------------------------------------------------------- modelling helpers
def edges_of(shape):
    m = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(shape, TopAbs_EDGE, m)
    return [TopoDS.Edge(m.FindKey(i)) for i in range(1, m.Extent() + 1)]


def faces_of(shape):
    m = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(shape, TopAbs_FACE, m)
    return [TopoDS.Face(m.FindKey(i)) for i in range(1, m.Extent() + 1)]


def edge_points(e, n=5):
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    a = BRepAdaptor_Curve(e)
    t0, t1 = a.FirstParameter(), a.LastParameter()
    out = []
    for k in range(n):
        p = a.Value(t0 + (t1 - t0) * (k + 0.5) / n)
        out.append((p.X(), p.Y(), p.Z()))
    return np.array(out)


def select_edges(shape, pred):
    """Edges all of whose sample points satisfy pred(x, y, z)."""
    return [e for e in edges_of(shape) if not BRep_Tool.Degenerated_s(e)
            and all(pred(*p) for p in edge_points(e))]


def fillet(shape, edges, r):
    mk = BRepFilletAPI_MakeFillet(shape)
    for e in edges:
        mk.Add(r, e)
    mk.Build()
    assert mk.IsDone(), "fillet failed"
    return mk.Shape()


def chamfer(shape, edges, d):
    mk = BRepFilletAPI_MakeChamfer(shape)
    for e in edges:
        mk.Add(d, e)
    mk.Build()
    assert mk.IsDone(), "chamfer failed"
    return mk.Shape()


def cut(a, b):
    op = BRepAlgoAPI_Cut(a, b)
    assert op.IsDone()
    return op.Shape()


def fuse(a, b):
    op = BRepAlgoAPI_Fuse(a, b)
    assert op.IsDone()
    op.SimplifyResult()
    return op.Shape()


def cyl(x, y, z, r, h, axis=(0, 0, 1)):
    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z), gp_Dir(*axis)), r, h).Shape()


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def polygon_prism(pts, vec):
    poly = BRepBuilderAPI_MakePolygon()
    for p in pts:
        poly.Add(gp_Pnt(*p))
    poly.Close()
    face = BRepBuilderAPI_MakeFace(poly.Wire()).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(*vec)).Shape()


def revolve_profile(pts_xz):
    """Closed polygon in the XZ plane (x = radius >= 0), revolved about Z."""
    poly = BRepBuilderAPI_MakePolygon()
    for x, z in pts_xz:
        poly.Add(gp_Pnt(x, 0, z))
    poly.Close()
    face = BRepBuilderAPI_MakeFace(poly.Wire()).Face()
    return BRepPrimAPI_MakeRevol(face, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2 * math.pi).Shape()


# ---------------------------------------------------------------- the parts
def flanged_bushing():
    # flange R30 h8, body R18 up to z=40, bore R10, six R3 bolt holes on R24,
    # R3 fillet where body meets flange (tangent), chamfers on bore top and body top rim.
    s = fuse(cyl(0, 0, 0, 30, 8), cyl(0, 0, 8, 18, 32))
    s = fillet(s, select_edges(s, lambda x, y, z: abs(z - 8) < 1e-6 and abs(math.hypot(x, y) - 18) < 1e-6), 3)
    s = cut(s, cyl(0, 0, -1, 10, 42))
    for k in range(6):
        a = 2 * math.pi * k / 6
        s = cut(s, cyl(24 * math.cos(a), 24 * math.sin(a), -1, 3, 10))
    s = chamfer(s, select_edges(s, lambda x, y, z: abs(z - 40) < 1e-6), 1.5)
    return s


def l_bracket():
    # L profile (XZ), extruded 40 along Y; R6 fillet on the inner bend; chamfered hole in the
    # base, plain hole in the upright; outer corner sharp.
    t = 8
    prof = [(0, 0, 0), (60, 0, 0), (60, 0, t), (t, 0, t), (t, 0, 50), (0, 0, 50)]
    s = polygon_prism(prof, (0, 40, 0))
    s = fillet(s, select_edges(s, lambda x, y, z: abs(x - t) < 1e-6 and abs(z - t) < 1e-6), 6)
    s = cut(s, cyl(38, 20, -1, 5, t + 2))
    s = chamfer(s, select_edges(s, lambda x, y, z: abs(z - t) < 1e-6 and abs(math.hypot(x - 38, y - 20) - 5) < 1e-6), 1.2)
    s = cut(s, cyl(-1, 20, 32, 4, t + 2, axis=(1, 0, 0)))
    return s


def gear_disc():
    # 20 trapezoidal teeth (tip R40, root R34, one straight root segment between teeth), thickness 10, bore R8 with a 45-degree chamfer 1.
    n, rt, rr, h = 20, 40.0, 34.0, 10.0
    pts = []
    for k in range(n):
        a0 = 2 * math.pi * k / n
        step = 2 * math.pi / n
        for frac, r in ((0.2, rr), (0.35, rt), (0.65, rt), (0.8, rr)):
            a = a0 + frac * step
            pts.append((r * math.cos(a), r * math.sin(a), 0))
    s = polygon_prism(pts, (0, 0, h))
    s = cut(s, cyl(0, 0, -1, 8, h + 2))
    s = chamfer(s, select_edges(s, lambda x, y, z: abs(z - h) < 1e-6 and abs(math.hypot(x, y) - 8) < 1e-6), 1.0)
    return s


def stepped_shaft():
    # radii 10 / 14 / 12 along Z (0-30, 30-70, 70-100), end chamfers 1 (in the profile),
    # a 3-wide 1.5-deep rectangular groove at z 48-51, a 45-degree V groove at z 85,
    # R1.5 fillet at the 14->12 step (tangent), the 10->14 step stays sharp.
    prof = [(0, 0), (9, 0), (10, 1), (10, 30), (14, 30), (14, 48), (12.5, 48), (12.5, 51), (14, 51),
            (14, 70), (12, 70), (12, 84), (11, 85), (12, 86), (12, 99), (11, 100), (0, 100)]
    s = revolve_profile(prof)
    s = fillet(s, select_edges(s, lambda x, y, z: abs(z - 70) < 1e-6 and abs(math.hypot(x, y) - 12) < 1e-6), 1.5)
    return s


def pocket_plate():
    # plate 80x60x12, pocket 50x30x6 from the top, R5 on the pocket's vertical corners,
    # R2 where the floor meets the walls (both tangent); outer edges and pocket rim sharp.
    s = cut(box(0, 0, 0, 80, 60, 12), box(15, 15, 6, 65, 45, 13))
    vert = select_edges(s, lambda x, y, z: 6 < z < 12 and 14 < x < 66 and 14 < y < 46)
    s = fillet(s, vert, 5)
    floor = select_edges(s, lambda x, y, z: abs(z - 6) < 1e-6)
    s = fillet(s, floor, 2)
    return s


def roof_wedge():
    # block 80 (X) x 50 (Y), walls 20 high, gable roof with 2.5-degree slopes: the ridge is a
    # 5-degree crease (hard); eaves meet the walls at 92.5 degrees.
    w, hwall = 50.0, 20.0
    rise = (w / 2) * math.tan(math.radians(2.5))
    prof = [(0, 0, 0), (0, w, 0), (0, w, hwall), (0, w / 2, hwall + rise), (0, 0, hwall)]
    return polygon_prism(prof, (80, 0, 0))


def cone_sphere_cap():
    # cone (base R25, top R10, height 30) whose top is closed by a sphere cap that is NOT tangent
    # (sphere R 14, centre below the top): a crease of about 20 degrees; base rim sharp.
    cone = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 25, 10, 30).Shape()
    rs = 14.0
    zc = 30 - math.sqrt(rs * rs - 10 * 10)
    sph = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, zc), rs).Shape()
    s = fuse(cone, cut(sph, box(-20, -20, zc - 20, 20, 20, 30)))
    return s


PARTS = dict(flanged_bushing=flanged_bushing, l_bracket=l_bracket, gear_disc=gear_disc,
             stepped_shaft=stepped_shaft, pocket_plate=pocket_plate, roof_wedge=roof_wedge,
             cone_sphere_cap=cone_sphere_cap)


# ---------------------------------------------------------------- sharp B-rep edges
def face_normal_at_edge(face, edge, t):
    c2d = BRep_Tool.CurveOnSurface_s(edge, face, 0.0, 0.0)
    uv = c2d.Value(t)
    gf = BRepGProp_Face(face)  # reverses the normal for reversed faces
    p, v = gp_Pnt(), gp_Vec()
    gf.Normal(uv.X(), uv.Y(), p, v)
    n = np.array([v.X(), v.Y(), v.Z()])
    L = np.linalg.norm(n)
    return n / L if L > 1e-12 else None


def sharp_edges(shape):
    """(edge, max dihedral angle in degrees) for every edge; angle None for seams/degenerate."""
    anc = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, anc)
    out = []
    for i in range(1, anc.Extent() + 1):
        e = TopoDS.Edge(anc.FindKey(i))
        fl = []
        for f in anc.FindFromIndex(i):
            if not any(f.IsSame(g) for g in fl):
                fl.append(f)
        if BRep_Tool.Degenerated_s(e) or len(fl) != 2:
            out.append((e, None))
            continue
        f1, f2 = TopoDS.Face(fl[0]), TopoDS.Face(fl[1])
        t0, t1 = BRep_Tool.Range_s(e)
        worst = 0.0
        for k in range(21):
            t = t0 + (t1 - t0) * k / 20
            n1, n2 = face_normal_at_edge(f1, e, t), face_normal_at_edge(f2, e, t)
            if n1 is None or n2 is None:
                continue
            worst = max(worst, math.degrees(math.acos(max(-1.0, min(1.0, float(n1 @ n2))))))
        out.append((e, worst))
    return out


def diagonal(shape):
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    lo, hi = b.CornerMin(), b.CornerMax()
    return lo.Distance(hi)


# ---------------------------------------------------------------- meshing
class Welder:
    def __init__(self, tol):
        self.tol, self.keys, self.pts = tol, {}, []

    def add(self, p):
        k = tuple(int(round(c / self.tol)) for c in p)
        for dk in [(0, 0, 0)] + [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]:
            kk = (k[0] + dk[0], k[1] + dk[1], k[2] + dk[2])
            if kk in self.keys and math.dist(self.pts[self.keys[kk]], p) <= self.tol:
                return self.keys[kk]
        self.keys[k] = len(self.pts)
        self.pts.append(tuple(p))
        return self.keys[k]


def mesh_export(shape, diag, sharp):
    BRepMesh_IncrementalMesh(shape, 5e-4 * diag, False, 0.5, False)
    W = Welder(1e-7 * diag)
    tris, fea = [], set()
    sharp_list = [e for e, a in sharp if a is not None and a > SHARP_DEG]
    anc = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, anc)
    for face in faces_of(shape):
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        assert tri is not None, "face without triangulation"
        tr = loc.Transformation()
        idx = [None] + [W.add((q.X(), q.Y(), q.Z())) for q in
                        (tri.Node(i).Transformed(tr) for i in range(1, tri.NbNodes() + 1))]
        rev = face.Orientation() == TopAbs_REVERSED
        for i in range(1, tri.NbTriangles() + 1):
            a, b, c = tri.Triangle(i).Get()
            tris.append((idx[a], idx[c], idx[b]) if rev else (idx[a], idx[b], idx[c]))
        for e in sharp_list:
            poly = BRep_Tool.PolygonOnTriangulation_s(e, tri, loc)
            if poly is None:
                continue
            nodes = [poly.Node(k) for k in range(1, poly.NbNodes() + 1)]
            for a, b in zip(nodes, nodes[1:]):
                if idx[a] != idx[b]:
                    fea.add((min(idx[a], idx[b]), max(idx[a], idx[b])))
    V = np.array(W.pts)
    T = np.array([t for t in tris if len(set(t)) == 3])
    return V, T, sorted(fea)


def mesh_uniform(shape, diag, sharp, brep_path):
    import gmsh
    BRepTools.Write_s(shape, str(brep_path))
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.model.add("part")
    gmsh.option.setNumber("Geometry.OCCFixDegenerated", 0)
    gmsh.option.setNumber("Geometry.OCCFixSmallEdges", 0)
    gmsh.option.setNumber("Geometry.OCCFixSmallFaces", 0)
    gmsh.option.setNumber("Geometry.OCCSewFaces", 0)
    gmsh.model.occ.importShapes(str(brep_path))
    gmsh.model.occ.synchronize()
    h = 0.01 * diag
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.model.mesh.generate(2)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    xyz = xyz.reshape(-1, 3)
    pos = {int(t): xyz[i] for i, t in enumerate(tags)}
    # classify every gmsh curve by the B-rep edge its parametric midpoint lies on
    sharp_edges_occ = [e for e, a in sharp if a is not None and a > SHARP_DEG]
    pairs = []
    for _, ctag in gmsh.model.getEntities(1):
        lo, hi = gmsh.model.getParametrizationBounds(1, ctag)
        hits = 0
        for frac in (0.37, 0.5, 0.71):
            p = gmsh.model.getValue(1, ctag, [lo[0] + frac * (hi[0] - lo[0])])
            v = BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex()
            if any(BRepExtrema_DistShapeShape(v, e).Value() < 1e-6 * diag for e in sharp_edges_occ):
                hits += 1
        assert hits in (0, 3), f"curve {ctag}: ambiguous ({hits}/3 samples on sharp edges)"
        if hits:
            etypes, _, enodes = gmsh.model.mesh.getElements(1, ctag)
            for et, en in zip(etypes, enodes):
                assert et == 1
                pairs += [(int(a), int(b)) for a, b in np.asarray(en).reshape(-1, 2)]
    et, _, en = gmsh.model.mesh.getElements(2, -1)
    tri_nodes = np.concatenate([np.asarray(n).reshape(-1, 3) for t, n in zip(et, en) if t == 2])
    gmsh.finalize()
    # weld by position too (gmsh keeps curve nodes shared, but be safe) and renumber
    W = Welder(1e-7 * diag)
    remap = {t: W.add(tuple(pos[t])) for t in sorted(set(tri_nodes.ravel().tolist()))}
    T = np.array([[remap[int(a)] for a in t] for t in tri_nodes])
    T = T[[len(set(t)) == 3 for t in T]]
    fea = sorted({(min(remap[a], remap[b]), max(remap[a], remap[b])) for a, b in pairs if remap[a] != remap[b]})
    return np.array(W.pts), orient(T), fea


def orient(T):
    """Consistent winding by BFS, then positive volume per component."""
    from collections import defaultdict, deque
    T = [list(t) for t in T]
    e2t = defaultdict(list)
    for i, t in enumerate(T):
        for k in range(3):
            e2t[frozenset((t[k], t[(k + 1) % 3]))].append(i)
    seen = [False] * len(T)
    for s in range(len(T)):
        if seen[s]:
            continue
        seen[s] = True
        q = deque([s])
        while q:
            i = q.popleft()
            t = T[i]
            for k in range(3):
                a, b = t[k], t[(k + 1) % 3]
                for j in e2t[frozenset((a, b))]:
                    if seen[j]:
                        continue
                    u = T[j]
                    # consistent if neighbour has edge b->a
                    if any(u[m] == a and u[(m + 1) % 3] == b for m in range(3)):
                        T[j] = [u[0], u[2], u[1]]
                    seen[j] = True
                    q.append(j)
    return np.array(T)


def fix_volume(V, T):
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    vol = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    return T if vol > 0 else T[:, [0, 2, 1]]


def write(out, name, kind, V, T, fea, note):
    T = fix_volume(V, orient(T))
    with open(out / f"{name}-{kind}.obj", "w") as f:
        f.write(f"# {name}: {note}; sharp B-rep edges in {name}-{kind}.fea\n")
        for p in V:
            f.write("v %.9g %.9g %.9g\n" % tuple(p))
        for t in T:
            f.write("f %d %d %d\n" % tuple(np.asarray(t) + 1))
    with open(out / f"{name}-{kind}.fea", "w") as f:
        f.write(f"{len(fea)}\n")
        for a, b in fea:
            f.write(f"{a} {b}\n")
    # also a line OBJ of the truth, for rendering checks
    with open(out.parent / "truth" / f"{name}-{kind}-truth.obj", "w") as f:
        used = sorted({i for e in fea for i in e})
        m = {i: k + 1 for k, i in enumerate(used)}
        f.write("o crease-ridges\n")
        for i in used:
            f.write("v %.9g %.9g %.9g\n" % tuple(V[i]))
        for a, b in fea:
            f.write(f"l {m[a]} {m[b]}\n")
    L = sum(np.linalg.norm(V[a] - V[b]) for a, b in fea)
    return L


def main():
    args = sys.argv[1:]
    only = args[args.index("--only") + 1] if "--only" in args else None
    pos = [a for a in args if not a.startswith("--") and a != only]
    out = Path(pos[0] if pos else "cad_parts")
    out.mkdir(parents=True, exist_ok=True)
    (out.parent / "truth").mkdir(exist_ok=True)
    (out.parent / "brep").mkdir(exist_ok=True)
    for name, make in PARTS.items():
        if only and only != name:
            continue
        s = make()
        assert BRepCheck_Analyzer(s).IsValid(), f"{name}: invalid B-rep"
        d = diagonal(s)
        sh = sharp_edges(s)
        ns = sum(1 for _, a in sh if a is not None and a > SHARP_DEG)
        angles = sorted({round(a, 2) for _, a in sh if a is not None})
        print(f"{name}: diag {d:.2f}, {len(sh)} edges, {ns} sharp; distinct max angles {angles}")
        V, T, fea = mesh_export(s, d, sh)
        Le = write(out, name, "export", V, T, fea, "OpenCASCADE tessellation, deflection 5e-4 diag")
        print(f"  export : {len(V)} v {len(T)} f, {len(fea)} sharp mesh edges, length {Le / d:.3f} diag")
        V, T, fea = mesh_uniform(s, d, sh, out.parent / "brep" / f"{name}.brep")
        Lu = write(out, name, "uniform", V, T, fea, "gmsh, edge 1% of the diagonal")
        print(f"  uniform: {len(V)} v {len(T)} f, {len(fea)} sharp mesh edges, length {Lu / d:.3f} diag")


if __name__ == "__main__":
    main()
