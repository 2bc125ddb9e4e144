// cmr_step_model OUT.step [COPIES]: writes the small CAD model of the STEP QA example
// and tests (docs/space.md, "QA of a CAD model") with OpenCASCADE, so that no
// model is downloaded or committed as a binary:
//  - a 40 x 30 x 20 box with its 12 edges filleted (radius 4): lines,
//    circles and the B-spline edges OCCT builds where three fillets meet;
//  - a smooth loft (BRepOffsetAPI_ThruSections) through a circle and two
//    closed interpolated B-spline sections above it: B-spline edges (the
//    sections and the seam);
//  - an interpolated cubic B-spline edge through points of a helix
//    (GeomAPI_Interpolate, non-uniform knots), a rational B-spline edge (a
//    circle arc converted, GeomConvert), a Bezier edge of degree 5, and a
//    clamped quartic B-spline with an interior triple knot.
// COPIES (default 1) places that many copies side by side, 200 apart in y
// (the benchmark's larger model). `cmr_step_model OUT.step seed` writes the
// STEP fuzz harness's small seed instead (fuzz/corpus/step): one cubic
// B-spline edge, one Bezier edge of degree 3 and a circle's edge; `wire`
// the class-A-style wire of the chains example (class_a_wire below);
// `spiral` and `spiral-dent` the chain of the chain-fix example (spiral_wire
// below). Deterministic: the same file on every run
// (the writer's time stamp aside).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepOffsetAPI_ThruSections.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <GC_MakeCircle.hxx>
#include <GeomAPI_Interpolate.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_Circle.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_HArray1OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Trsf.hxx>

namespace {

TopoDS_Shape filleted_box() {
  BRepPrimAPI_MakeBox box(40, 30, 20);
  BRepFilletAPI_MakeFillet fillet(box.Shape());
  for (TopExp_Explorer e(box.Shape(), TopAbs_EDGE); e.More(); e.Next()) fillet.Add(4, TopoDS::Edge(e.Current()));
  return fillet.Shape();
}

Handle(Geom_BSplineCurve) interpolate(const std::vector<gp_Pnt>& pts, bool periodic) {
  Handle(TColgp_HArray1OfPnt) a = new TColgp_HArray1OfPnt(1, static_cast<int>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) a->SetValue(static_cast<int>(i) + 1, pts[i]);
  GeomAPI_Interpolate in(a, periodic, 1e-7);
  in.Perform();
  return in.Curve();
}

TopoDS_Shape loft() {
  BRepOffsetAPI_ThruSections thru(Standard_True, Standard_False);
  const gp_Circ circle(gp_Ax2(gp_Pnt(80, 0, 0), gp_Dir(0, 0, 1)), 10);
  thru.AddWire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circle)));
  std::vector<gp_Pnt> ring;
  for (int i = 0; i < 7; ++i) {
    const double a = 2 * M_PI * i / 7;
    const double r = 12 + 3 * std::cos(3 * a);
    ring.emplace_back(80 + r * std::cos(a), r * std::sin(a), 30 + 2 * std::sin(2 * a));
  }
  thru.AddWire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(interpolate(ring, true))));
  std::vector<gp_Pnt> top;
  for (int i = 0; i < 9; ++i) {
    const double a = 2 * M_PI * i / 9;
    top.emplace_back(84 + 6 * std::cos(a), 4 * std::sin(a), 50 + std::cos(a));
  }
  thru.AddWire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(interpolate(top, true))));
  thru.Build();
  return thru.Shape();
}

}  // namespace

// The class-A-style wire (`cmr_step_model OUT.step wire`; docs/space.md,
// "Chains of edges"): four B-spline edges in one wire, e1 > e2 > e3 > e4,
// in the plane z = 0, closed by a line into the boundary of a planar face
// (STEP keeps a wire's shared vertices in a face; a free wire is written as
// unconnected curves).
// e1 and e2 are one quintic B-spline (simple knots: C4) cut at an interior
// parameter: their junction is G3. e3 and e4 are a second quintic with a
// triple knot (C2 there) cut at that knot: G2, not G3. The second curve
// starts at the first's end along its end tangent with another speed and
// curvature: that junction is G1 only.
TopoDS_Shape class_a_wire() {
  const auto quintic = [](const std::vector<gp_Pnt>& pts, const std::vector<double>& knots, const std::vector<int>& mults) {
    TColgp_Array1OfPnt poles(1, static_cast<int>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) poles.SetValue(static_cast<int>(i) + 1, pts[i]);
    TColStd_Array1OfReal k(1, static_cast<int>(knots.size()));
    TColStd_Array1OfInteger m(1, static_cast<int>(knots.size()));
    for (std::size_t i = 0; i < knots.size(); ++i) k.SetValue(static_cast<int>(i) + 1, knots[i]), m.SetValue(static_cast<int>(i) + 1, mults[i]);
    return Handle(Geom_BSplineCurve)(new Geom_BSplineCurve(poles, k, m, 5));
  };
  // A widening spiral: its curvature falls along it.
  std::vector<gp_Pnt> a;
  for (int i = 0; i < 9; ++i) {
    const double t = 0.45 * i, r = 10 + 2.2 * i;
    a.emplace_back(r * std::cos(t), r * std::sin(t), 0);
  }
  const Handle(Geom_BSplineCurve) first = quintic(a, {0, 1, 2, 3, 4}, {6, 1, 1, 1, 6});
  // The second curve: its first leg along the first's end tangent (G1), then on.
  gp_Pnt end;
  gp_Vec d1;
  first->D1(first->LastParameter(), end, d1);
  const gp_Vec u = d1.Normalized();
  std::vector<gp_Pnt> b{end, end.Translated(u * 6)};
  for (int i = 2; i < 10; ++i) {
    const gp_Pnt p = b.back();
    const double t = 0.3 * i;
    b.push_back(p.Translated(gp_Vec(u.X() * 5 + 2 * std::sin(t), u.Y() * 5 + 2 * std::cos(t), 0)));
  }
  const Handle(Geom_BSplineCurve) second = quintic(b, {0, 1, 2, 3}, {6, 1, 3, 6});  // 10 poles = 16 - 5 - 1
  const double cut = 2.2;
  BRepBuilderAPI_MakeWire wire;
  const Handle(Geom_BSplineCurve) e1 = Handle(Geom_BSplineCurve)::DownCast(first->Copy());
  const Handle(Geom_BSplineCurve) e2 = Handle(Geom_BSplineCurve)::DownCast(first->Copy());
  e1->Segment(0, cut), e2->Segment(cut, 4);
  const Handle(Geom_BSplineCurve) e3 = Handle(Geom_BSplineCurve)::DownCast(second->Copy());
  const Handle(Geom_BSplineCurve) e4 = Handle(Geom_BSplineCurve)::DownCast(second->Copy());
  e3->Segment(0, 2), e4->Segment(2, 3);
  for (const Handle(Geom_BSplineCurve)& e : {e1, e2, e3, e4}) wire.Add(BRepBuilderAPI_MakeEdge(e).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(e4->EndPoint(), e1->StartPoint()).Edge());  // the line that closes it
  return BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
}

// The chain-fix example (`cmr_step_model OUT.step spiral|spiral-dent`;
// docs/space.md, "Chains of edges"): a quintic B-spline whose 24 poles lie on
// a discrete logarithmic spiral, P_i = 10 * 1.08^i (cos 0.35 i, sin 0.35 i, 0),
// on uniform knots 0..29. Each span is then the image of the one before it
// by one similarity (rotate 0.35, scale 1.08), so |kappa| falls by 1.08 from
// each span to the next, and it falls inside one span (cmr's analysis says
// so): the curve's |kappa| decreases throughout. Its 19 spans [5, 24] are cut
// at the simple knot 14 into two edges (C4 there: a G3 junction), e1 with 9
// spans and e2 with 10, closed by a line into a planar face. `spiral-dent`
// pushes pole 7 15 % outwards: its B-spline is non-zero on (7, 13) only,
// inside e1, so e1's |kappa| is no longer monotone while both of e1's ends,
// and the junction, are what they were; `cmr fix OUT.step --chain 1`
// repairs it with the junction kept.
TopoDS_Shape spiral_wire(bool dent) {
  TColgp_Array1OfPnt poles(1, 24);
  for (int i = 0; i < 24; ++i) {
    const double r = 10 * std::pow(1.08, i) * (dent && i == 7 ? 1.15 : 1.0), a = 0.35 * i;
    poles.SetValue(i + 1, gp_Pnt(r * std::cos(a), r * std::sin(a), 0));
  }
  TColStd_Array1OfReal knots(1, 30);  // 24 poles + degree 5 + 1, each once: not clamped
  TColStd_Array1OfInteger mults(1, 30);
  for (int i = 1; i <= 30; ++i) knots.SetValue(i, i - 1), mults.SetValue(i, 1);
  const Handle(Geom_BSplineCurve) curve = new Geom_BSplineCurve(poles, knots, mults, 5);
  const Handle(Geom_BSplineCurve) e1 = Handle(Geom_BSplineCurve)::DownCast(curve->Copy());
  const Handle(Geom_BSplineCurve) e2 = Handle(Geom_BSplineCurve)::DownCast(curve->Copy());
  e1->Segment(5, 14), e2->Segment(14, 24);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(e1).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(e2).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(e2->EndPoint(), e1->StartPoint()).Edge());  // the line that closes it
  return BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
}

// The fuzz seed: a few edges, a few KB of STEP.
TopoDS_Shape seed() {
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  b.Add(c, BRepBuilderAPI_MakeEdge(interpolate({{0, 0, 0}, {1, 2, 0.5}, {3, 1, 1}, {4, 3, 0}, {6, 2, -1}}, false)));
  TColgp_Array1OfPnt bez(1, 4);
  for (int i = 0; i < 4; ++i) bez.SetValue(i + 1, gp_Pnt(i, i * i % 3, 1 - i));
  b.Add(c, BRepBuilderAPI_MakeEdge(Handle(Geom_BezierCurve)(new Geom_BezierCurve(bez))));
  b.Add(c, BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0, 5, 0), gp_Dir(0, 0, 1)), 2)));
  return c;
}

bool write_step(const TopoDS_Shape& shape, const char* path) {
  STEPControl_Writer writer;
  Interface_Static::SetCVal("write.step.schema", "AP214CD");
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone) {
    std::fprintf(stderr, "cmr_step_model: OpenCASCADE could not transfer the model\n");
    return false;
  }
  if (writer.Write(path) != IFSelect_RetDone) {
    std::fprintf(stderr, "cmr_step_model: %s: cannot write the STEP file\n", path);
    return false;
  }
  return true;
}

int main(int argc, char** argv) {
  const std::string kind = argc == 3 ? argv[2] : "";
  if (kind == "seed" || kind == "wire" || kind == "spiral" || kind == "spiral-dent") {
    Message::DefaultMessenger()->ChangePrinters().Clear();
    try {
      const TopoDS_Shape shape = kind == "seed" ? seed() : kind == "wire" ? class_a_wire() : spiral_wire(kind == "spiral-dent");
      return write_step(shape, argv[1]) ? 0 : 3;
    } catch (const Standard_Failure& f) {
      std::fprintf(stderr, "cmr_step_model: OpenCASCADE: %s\n", f.GetMessageString());
      return 3;
    }
  }
  const int copies = argc == 3 ? std::atoi(argv[2]) : 1;
  if ((argc != 2 && argc != 3) || copies < 1 || copies > 10000) {
    std::fprintf(stderr, "usage: cmr_step_model OUT.step [COPIES 1..10000 | seed | wire | spiral | spiral-dent]\n");
    return 2;
  }
  Message::DefaultMessenger()->ChangePrinters().Clear();  // OCCT's progress lines
  try {
    BRep_Builder b;
    TopoDS_Compound model;
    b.MakeCompound(model);
    b.Add(model, filleted_box());
    b.Add(model, loft());
    std::vector<gp_Pnt> helix;
    for (int i = 0; i <= 12; ++i) {
      const double a = 0.5 * i + 0.02 * i * i;  // unequal steps: non-uniform knots
      helix.emplace_back(-40 + 15 * std::cos(a), 15 * std::sin(a), 2.5 * a);
    }
    b.Add(model, BRepBuilderAPI_MakeEdge(interpolate(helix, false)));
    const Handle(Geom_TrimmedCurve) arc = GC_MakeArcOfCircle(gp_Circ(gp_Ax2(gp_Pnt(0, -50, 10), gp_Dir(1, 1, 1)), 12), 0.3, 2.6, true);
    b.Add(model, BRepBuilderAPI_MakeEdge(GeomConvert::CurveToBSplineCurve(arc)));
    TColgp_Array1OfPnt bez(1, 6);
    const double bp[6][3] = {{0, -80, 0}, {10, -75, 5}, {20, -82, 12}, {30, -70, 14}, {40, -78, 9}, {50, -74, 0}};
    for (int i = 0; i < 6; ++i) bez.SetValue(i + 1, gp_Pnt(bp[i][0], bp[i][1], bp[i][2]));
    b.Add(model, BRepBuilderAPI_MakeEdge(Handle(Geom_BezierCurve)(new Geom_BezierCurve(bez))));
    TColgp_Array1OfPnt poles(1, 8);
    for (int i = 0; i < 8; ++i) poles.SetValue(i + 1, gp_Pnt(70 + 6 * i, -60 + 4 * std::sin(i), 3 * std::cos(0.7 * i)));
    TColStd_Array1OfReal knots(1, 3);
    TColStd_Array1OfInteger mults(1, 3);
    knots.SetValue(1, 0), knots.SetValue(2, 1.5), knots.SetValue(3, 4);
    mults.SetValue(1, 5), mults.SetValue(2, 3), mults.SetValue(3, 5);  // 5 + 3 + 5 = 8 + 4 + 1
    b.Add(model, BRepBuilderAPI_MakeEdge(Handle(Geom_BSplineCurve)(new Geom_BSplineCurve(poles, knots, mults, 4))));
    TopoDS_Compound all;
    b.MakeCompound(all);
    for (int k = 0; k < copies; ++k) {
      gp_Trsf shift;
      shift.SetTranslation(gp_Vec(0, 200.0 * k, 0));
      b.Add(all, k == 0 ? TopoDS_Shape(model) : BRepBuilderAPI_Transform(model, shift, true).Shape());
    }
    if (!write_step(all, argv[1])) return 3;
  } catch (const Standard_Failure& f) {
    std::fprintf(stderr, "cmr_step_model: OpenCASCADE: %s\n", f.GetMessageString());
    return 3;
  }
  return 0;
}
