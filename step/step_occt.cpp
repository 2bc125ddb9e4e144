// The STEP importer through OpenCASCADE (step/step.hpp).
#include <sys/prctl.h>
#include <sys/wait.h>

#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Vec.hxx>
#include <set>
#include <unordered_map>
#include "bezierize/space_analyze.hpp"
#include <BndLib_Add3dCurve.hxx>
#include <Bnd_Box.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <StepBasic_Product.hxx>
#include <StepBasic_ProductDefinition.hxx>
#include <StepBasic_ProductDefinitionFormation.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TransferBRep.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shape.hxx>

#include "io/output.hpp"
#include "spline/errors.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"
#include "step/step.hpp"
#include "step/step_occt.hpp"

namespace cmr::import {

namespace {

// OCCT's reader reports through Message::DefaultMessenger (to standard
// output): cmr's standard output is its JSON, so the printers go, once.
void silence_occt() {
  static const bool done = [] {
    Message::DefaultMessenger()->ChangePrinters().Clear();
    return true;
  }();
  (void)done;
}

// cmr's spline of the homogeneous coordinates (w x, w y, w z) and of w (as
// (w, 0, 0)), to evaluate the converted rational curve with cmr's own code.
double conversion_error(const StepCurve& c, const Handle(Geom_BSplineCurve) & g) {
  std::vector<Vec3> num, den;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const double w = c.weights.empty() ? 1.0 : c.weights[i];
    num.push_back(c.points[i] * w);
    den.push_back({w, 0, 0});
  }
  const auto make = [&](std::vector<Vec3> p) {
    return c.closed ? SpaceSpline::make_closed(c.degree, c.knots, std::move(p))
                    : SpaceSpline::make(c.degree, c.knots, std::move(p));
  };
  const SpaceSpline n = make(num), d = make(den);
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const Vec3& p : c.points)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300});
  double err = 0;
  const int samples = 8 * n.segment_count() + 1;
  for (int i = 0; i <= samples; ++i) {
    const double t = n.domain_begin() + (n.domain_end() - n.domain_begin()) * i / samples;
    const Vec3 p = evaluate(n, t) / evaluate(d, t).x;
    const gp_Pnt q = g->Value(t);
    err = std::max({err, std::abs(p.x - q.X()), std::abs(p.y - q.Y()), std::abs(p.z - q.Z())});
  }
  return err / size;
}

void fill_common(StepCurve& c, const Handle(Geom_BSplineCurve) & g) {
  c.degree = g->Degree();
  c.points.clear();
  c.weights.clear();
  for (int i = 1; i <= g->NbPoles(); ++i) {
    const gp_Pnt p = g->Pole(i);
    c.points.push_back({p.X(), p.Y(), p.Z()});
  }
  if (g->IsRational()) {
    bool equal = true;
    for (int i = 1; i <= g->NbPoles(); ++i) {
      c.weights.push_back(g->Weight(i));
      equal = equal && g->Weight(i) == g->Weight(1);
    }
    if (equal) c.weights.clear();
  }
}

// The open form: the flat knots without the first and last one.
void fill_open(StepCurve& c, const Handle(Geom_BSplineCurve) & g) {
  fill_common(c, g);
  const TColStd_Array1OfReal& flat = g->KnotSequence();
  c.knots.assign(flat.begin() + 1, flat.end() - 1);
  c.closed = false;
}

// The closed form: the knots of one period, each as often as its
// multiplicity, the last (the seam again) once.
void fill_closed(StepCurve& c, const Handle(Geom_BSplineCurve) & g) {
  fill_common(c, g);
  c.knots.clear();
  for (int i = 1; i < g->NbKnots(); ++i)
    for (int k = 0; k < g->Multiplicity(i); ++k) c.knots.push_back(g->Knot(i));
  c.knots.push_back(g->Knot(g->NbKnots()));
  c.closed = true;
}

constexpr double kTolerance = 1e-9;

// An OCCT string as UTF-8: a STEP name's bytes (ISO 8859-1 in older files)
// that are not UTF-8 become U+FFFD, as JSON holds UTF-8 only.
std::string text_of(const Handle(TCollection_HAsciiString) & s) {
  std::string out;
  for (std::string_view rest = s.IsNull() ? "" : s->ToCString(); !rest.empty();) {
    const std::size_t n = utf8_sequence(rest);
    out.append(n == 0 ? std::string_view("\xEF\xBF\xBD") : rest.substr(0, n));
    rest.remove_prefix(n == 0 ? 1 : n);
  }
  return out;
}

// The entities the transfer bound to shapes (XSControl_TransferReader's
// TransientProcess: one binder per transferred entity).
StepTrace trace_of(const STEPControl_Reader& reader) {
  StepTrace trace;
  const Handle(XSControl_WorkSession) ws = reader.WS();
  const Handle(Interface_InterfaceModel) model = ws->Model();
  const Handle(Transfer_TransientProcess) tp = ws->TransferReader()->TransientProcess();
  if (model.IsNull() || tp.IsNull()) return trace;
  for (int i = 1; i <= model->NbEntities(); ++i) {
    const Handle(Standard_Transient) e = model->Value(i);
    const Handle(Transfer_Binder) binder = tp->Find(e);
    if (binder.IsNull()) continue;
    const TopoDS_Shape shape = TransferBRep::ShapeResult(binder);
    if (shape.IsNull()) continue;
    // The label the file gave the entity: "#1234".
    const std::string label = text_of(ws->EntityLabel(e));
    long long id = 0;
    if (label.size() > 1 && label[0] == '#') id = std::strtoll(label.c_str() + 1, nullptr, 10);
    if (id <= 0) continue;
    const void* key = shape.TShape().get();
    if (const Handle(StepBasic_ProductDefinition) pd = Handle(StepBasic_ProductDefinition)::DownCast(e); !pd.IsNull()) {
      std::string name;
      if (!pd->Formation().IsNull() && !pd->Formation()->OfProduct().IsNull()) name = text_of(pd->Formation()->OfProduct()->Name());
      TopTools_IndexedMapOfShape edges;
      TopExp::MapShapes(shape, TopAbs_EDGE, edges);
      for (int k = 1; k <= edges.Extent(); ++k) {
        StepTrace::Entity& p = trace.products[edges(k).TShape().get()];
        if (p.id == 0 || edges.Extent() < p.size) p = {id, name, edges.Extent()};
      }
      continue;
    }
    const Handle(StepRepr_RepresentationItem) item = Handle(StepRepr_RepresentationItem)::DownCast(e);
    if (item.IsNull()) continue;
    const StepTrace::Entity entity{id, text_of(item->Name()), 0};
    switch (shape.ShapeType()) {
      case TopAbs_EDGE: trace.edges.emplace(key, entity); break;
      case TopAbs_FACE: trace.faces.emplace(key, entity); break;
      case TopAbs_SHELL: trace.shells.emplace(key, entity); break;
      default: break;
    }
  }
  return trace;
}

// The names of an edge's face, shell and product (the first face and shell
// that hold it and have an entity).
void trace_edge(StepCurve& c, const TopoDS_Shape& edge, const StepTrace& trace,
                const TopTools_IndexedDataMapOfShapeListOfShape& faces_of_edge,
                const TopTools_IndexedDataMapOfShapeListOfShape& shells_of_face) {
  const auto find = [](const std::unordered_map<const void*, StepTrace::Entity>& m, const TopoDS_Shape& s) {
    const auto it = m.find(s.TShape().get());
    return it == m.end() ? nullptr : &it->second;
  };
  if (const StepTrace::Entity* e = find(trace.edges, edge)) c.origin.entity = e->id, c.origin.edge_name = e->name;
  if (const StepTrace::Entity* p = find(trace.products, edge)) c.origin.product_name = p->name;
  const int fi = faces_of_edge.FindIndex(edge);
  if (fi == 0) return;
  for (const TopoDS_Shape& face : faces_of_edge(fi)) {
    const StepTrace::Entity* f = find(trace.faces, face);
    if (f == nullptr) continue;
    c.origin.face_name = f->name;
    if (const int si = shells_of_face.FindIndex(face); si != 0)
      for (const TopoDS_Shape& shell : shells_of_face(si))
        if (const StepTrace::Entity* sh = find(trace.shells, shell)) {
          c.origin.shell_name = sh->name;
          break;
        }
    break;
  }
}

// The reader's checks, before the transfer: OCCT reads past a syntax error or
// a parameter of the wrong type (it keeps a null or undefined entity and
// records a fail), and its transfer then dereferences that null handle
// (SIGSEGV in STEPConstruct_Assembly::CheckSRRReversesNAUO, found by
// fuzz_step within seconds). A file with a fail is refused, naming the
// first one: "FILE: #3: OpenCASCADE could not read this entity (Parameter
// n0.1 (...) : Entity has illegal type)".
void refuse_failed_entities(const STEPControl_Reader& reader, const std::string& where) {
  const Interface_CheckIterator checks = reader.WS()->ModelCheckList();
  for (checks.Start(); checks.More(); checks.Next()) {
    const Handle(Interface_Check)& check = checks.Value();
    if (!check->HasFailed()) continue;
    std::string what = check->NbFails() > 0 ? check->CFail(1) : "a fail";
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::string m = where;
    if (!check->Entity().IsNull()) {
      m.append(": ").append(text_of(reader.WS()->EntityLabel(check->Entity())));
      m.append(": OpenCASCADE could not read this entity (").append(what).append(")");
    } else {
      m.append(": OpenCASCADE could not read it (").append(what).append(")");
    }
    throw InputError(m);
  }
}

// --- chains (step/step.hpp, StepChain) ---

struct EndDerivatives {
  gp_Pnt p;
  gp_Vec a, b, c;  // r', r'', r''' in the walking direction
};

EndDerivatives end_of(const Handle(Geom_BSplineCurve) & g, bool reversed, bool at_end) {
  // Walked forward, the chain leaves a curve at its last parameter; walked
  // reversed (t -> -t), at its first, with r' and r''' negated.
  const double t = (at_end != reversed) ? g->LastParameter() : g->FirstParameter();
  EndDerivatives d;
  g->D3(t, d.p, d.a, d.b, d.c);
  if (reversed) d.a.Reverse(), d.c.Reverse();
  return d;
}

struct Shape3 {
  double kappa = 0, tau = 0, dkds = 0;
  gp_Vec t, kvec;  // unit tangent, curvature vector kappa N
};

Shape3 shape3(const EndDerivatives& d) {
  Shape3 s;
  const double la = d.a.Magnitude();
  if (!(la > 0)) return s;
  s.t = d.a / la;
  const gp_Vec w = d.a.Crossed(d.b), w1 = d.a.Crossed(d.c);
  const double lw = w.Magnitude();
  s.kappa = lw / (la * la * la);
  s.kvec = w.Crossed(d.a) / (la * la * la * la);  // (a x b) x a / |a|^4 = kappa N
  if (lw > 0) {
    s.tau = w.Dot(d.c) / (lw * lw);
    s.dkds = (w.Dot(w1) / (lw * la * la * la) - 3 * lw * d.a.Dot(d.b) / std::pow(la, 5)) / la;
  }
  return s;
}

StepJunction junction(const EndDerivatives& l, const EndDerivatives& r, const ChainTolerances& tol) {
  StepJunction j;
  j.gap = l.p.Distance(r.p);
  j.at = {l.p.X(), l.p.Y(), l.p.Z()};
  const Shape3 L = shape3(l), R = shape3(r);
  j.kappa_left = L.kappa, j.kappa_right = R.kappa, j.dkds_left = L.dkds, j.dkds_right = R.dkds;
  j.tau_left = L.tau, j.tau_right = R.tau;
  const double c = std::clamp(L.t.Dot(R.t), -1.0, 1.0);
  j.angle_deg = std::acos(c) * 180 / M_PI;
  if (L.t.Magnitude() == 0 || R.t.Magnitude() == 0) j.angle_deg = 180;
  const double kmax = std::max(L.kappa, R.kappa);
  const bool g1 = j.angle_deg <= tol.angle_deg;
  const bool g2 = g1 && (L.kvec - R.kvec).Magnitude() <= tol.curvature_rel * kmax;
  const bool g3 = g2 && std::abs(L.dkds - R.dkds) <= tol.g3_rel * std::max({std::abs(L.dkds), std::abs(R.dkds), kmax * kmax}) &&
                  std::abs(L.tau - R.tau) <= tol.g3_rel * std::max({std::abs(L.tau), std::abs(R.tau), kmax});
  j.level = g3 ? 3 : g2 ? 2 : g1 ? 1 : 0;
  return j;
}

// The runs of converted edges in the wires of `shape`, each once.
void find_chains(const TopoDS_Shape& shape, StepCurves& out, const std::vector<Handle(Geom_BSplineCurve)>& geoms,
                 const std::unordered_map<const void*, std::size_t>& curve_of, const ChainTolerances& tol,
                 const std::string& where) {
  std::set<std::vector<std::size_t>> seen;
  // A run of a wire: its junctions (gaps refused), cut at corners into chains.
  const auto flush = [&](StepChain& run) {
    const std::size_t n = run.curves.size();
    if (n >= 2) {
      std::vector<StepJunction> js;
      for (std::size_t i = 0; i + 1 < n || (run.closed && i < n); ++i) {
        const std::size_t k = (i + 1) % n;
        const StepJunction j = junction(end_of(geoms[run.curves[i]], run.reversed[i], true),
                                        end_of(geoms[run.curves[k]], run.reversed[k], false), tol);
        if (!(j.gap <= tol.gap)) {
          std::string m = where;
          m.append(": chain ").append(step_edge_id(out.curves[run.curves[i]])).append(" > ");
          m.append(step_edge_id(out.curves[run.curves[k]])).append(": the edges' ends are ");
          char buf[96];
          std::snprintf(buf, sizeof buf, "%.6g apart at their shared vertex, more than the tolerance %.6g", j.gap, tol.gap);
          throw InputError(m.append(buf));
        }
        js.push_back(j);
      }
      // Cut at corners: a closed run with a corner starts after it.
      std::size_t start = 0;
      bool cut = false;
      for (std::size_t i = 0; i < js.size(); ++i)
        if (js[i].angle_deg > tol.corner_deg) start = (i + 1) % n, cut = true;
      StepChain chain;
      chain.closed = run.closed && !cut;
      const auto emit = [&] {
        if (chain.curves.size() >= 2) {
          std::vector<std::size_t> key = chain.curves;
          std::sort(key.begin(), key.end());
          if (seen.insert(key).second) out.chains.push_back(chain);
        }
        chain = StepChain{};
      };
      for (std::size_t s = 0; s < n; ++s) {
        const std::size_t i = (start + s) % n;
        chain.curves.push_back(run.curves[i]);
        chain.reversed.push_back(run.reversed[i]);
        const bool last = s + 1 == n;
        if (i < js.size() && (!last || chain.closed)) {
          if (js[i].angle_deg > tol.corner_deg) {
            emit();
            continue;
          }
          chain.junctions.push_back(js[i]);
        }
      }
      emit();
    }
    run = StepChain{};
  };
  for (TopExp_Explorer w(shape, TopAbs_WIRE); w.More(); w.Next()) {
    std::vector<std::size_t> idx;
    std::vector<bool> rev;
    std::vector<bool> converted;
    for (BRepTools_WireExplorer e(TopoDS::Wire(w.Current())); e.More(); e.Next()) {
      const auto it = curve_of.find(e.Current().TShape().get());
      converted.push_back(it != curve_of.end());
      idx.push_back(it == curve_of.end() ? 0 : it->second);
      rev.push_back(e.Current().Orientation() == TopAbs_REVERSED);
    }
    const std::size_t n = idx.size();
    const bool all = n >= 2 && std::all_of(converted.begin(), converted.end(), [](bool b) { return b; });
    const bool closed = all && BRep_Tool::IsClosed(w.Current());
    // Start after a gap (a skipped edge) so that a run through the wire's start stays one.
    std::size_t start = 0;
    if (!all)
      while (converted[start]) ++start;
    StepChain chain;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = (start + k) % n;
      if (!converted[i]) {
        flush(chain);
        continue;
      }
      chain.curves.push_back(idx[i]);
      chain.reversed.push_back(rev[i]);
    }
    chain.closed = closed;
    flush(chain);
  }
}

// OpenCASCADE's parser and transfer run first in a child process (fork),
// on the same bytes: some malformed files crash them (SIGSEGV in
// ReadStream's model loader, which no pre-scan has caught: fuzz_step). The
// child exits 0 when it finished (or refused the file); anything else (a
// signal, or a sanitizer's exit code) is a crash, and the file is refused
// before this process reads it. The read costs twice its time (the budget
// covers both). 0: no crash (or no fork possible, or other threads beside
// this one: read in-process).
}  // namespace

// Set in sanitizer builds only (weak: null otherwise).
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace {

// Other threads than the caller's: a child forked beside them may inherit a
// lock one of them held (the sanitizers' allocator's, or any library's) and
// never finish, so the probe forks only in a single-threaded process (cmr
// import, the editor's STEP read and the fuzzer are, when they read).
bool other_threads() {
  std::error_code ec;
  std::size_t n = 0;
  for (auto it = std::filesystem::directory_iterator("/proc/self/task", ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec))
    ++n;
  return !ec && n > 1;
}

int probe_crash(const std::string& text, const std::string& where) {
  if (other_threads()) return 0;
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) return 0;
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // the parent's end (cmr import's budget alarm) ends the child too
    if (::getppid() != parent) std::_Exit(0);  // it ended before the line above (reparented: to init or a subreaper)
    // A crash here ends the child by its signal, for the parent to read:
    // not through a handler inherited from the parent (a fuzzer's or a
    // sanitizer's would report the parent's input as its own finding).
    if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(sig, SIG_DFL);
    try {
      STEPControl_Reader reader;
      std::istringstream in(text);
      if (reader.ReadStream(where.c_str(), in) == IFSelect_RetDone) {
        refuse_failed_entities(reader, where);
        reader.TransferRoots();
      }
    } catch (...) {
    }
    std::_Exit(0);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 0;
  if (WIFSIGNALED(status)) return WTERMSIG(status);
  return WIFEXITED(status) && WEXITSTATUS(status) != 0 ? -WEXITSTATUS(status) : 0;
}

}  // namespace

bool step_supported() { return true; }

StepCurves shape_curves(const TopoDS_Shape& shape, const std::string& where, const StepTrace* trace,
                        const ChainTolerances& tolerances) {
  StepCurves out;
  std::vector<Handle(Geom_BSplineCurve)> geoms;  // parallel to out.curves: OCCT's curve of each
  std::unordered_map<const void*, std::size_t> curve_of;  // edge TShape -> index in out.curves
  try {
    TopTools_IndexedMapOfShape edges;
    TopTools_IndexedDataMapOfShapeListOfShape faces_of_edge, shells_of_face;
    if (!shape.IsNull()) {
      TopExp::MapShapes(shape, TopAbs_EDGE, edges);
      if (trace != nullptr) {
        TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, faces_of_edge);
        TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SHELL, shells_of_face);
      }
    }
    out.edges = edges.Extent();
    for (int e = 1; e <= edges.Extent(); ++e) {
      const TopoDS_Edge& edge = TopoDS::Edge(edges(e));
      StepCurve c;
      c.edge = e;
      if (trace != nullptr) trace_edge(c, edge, *trace, faces_of_edge, shells_of_face);
      double first = 0, last = 0;
      Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
      const auto skip = [&](const std::string& type) {
        ++out.skipped[type];
        if (c.origin.entity > 0) out.skipped_entities[c.origin.entity] = type;
      };
      if (curve.IsNull()) {
        skip("degenerated edge");
        continue;
      }
      {  // the box of the part the edge uses, before the basis curve replaces a trimmed one
        Bnd_Box box;
        BndLib_Add3dCurve::AddOptimal(GeomAdaptor_Curve(curve, std::min(first, last), std::max(first, last)), 0.0, box);
        box.SetGap(0.0);  // AddOptimal widens it by Precision::Confusion
        if (!box.IsVoid()) {
          double x0, y0, z0, x1, y1, z1;
          box.Get(x0, y0, z0, x1, y1, z1);
          c.box_min = {x0, y0, z0}, c.box_max = {x1, y1, z1};
        }
      }
      if (curve->IsKind(STANDARD_TYPE(Geom_TrimmedCurve)))
        curve = Handle(Geom_TrimmedCurve)::DownCast(curve)->BasisCurve();
      c.name = step_edge_label(c);  // in messages until the name is complete
      Handle(Geom_BSplineCurve) g;
      if (curve->IsKind(STANDARD_TYPE(Geom_BSplineCurve))) {
        c.type = "Geom_BSplineCurve";
        g = Handle(Geom_BSplineCurve)::DownCast(curve->Copy());
      } else if (curve->IsKind(STANDARD_TYPE(Geom_BezierCurve))) {
        c.type = "Geom_BezierCurve";
        g = GeomConvert::CurveToBSplineCurve(curve);
      } else {
        skip(curve->DynamicType()->Name());
        continue;
      }
      if (g->Degree() < 2) {  // a polyline: no curvature to judge (cmr's splines have degree >= 2)
        skip(c.type + " of degree 1");
        continue;
      }
      const double eps = Precision::PConfusion();
      if (first > last) std::swap(first, last);
      if (first > g->FirstParameter() + eps || last < g->LastParameter() - eps ||
          (g->IsPeriodic() && (std::abs(first - g->FirstParameter()) > eps || std::abs(last - g->LastParameter()) > eps))) {
        const double period = g->IsPeriodic() ? g->Period() : 0;
        g->Segment(first, last);
        c.trimmed = true;
        // Part of a periodic curve is an open curve (a whole period, shifted, stays closed).
        if (g->IsPeriodic() && last - first < period - eps) {
          g->SetNotPeriodic();
          c.unperiodised = true;
        }
      }
      if (g->IsPeriodic()) {
        fill_closed(c, g);
        bool ok = false;
        const std::vector<Vec3> poles = c.points;
        const std::vector<double> weights = c.weights;
        const std::size_t m = poles.size();
        // OCCT's first span [k1, k2] uses poles 1..d+1; cmr's first non-empty
        // span is u_{r-1} (r: k1's multiplicity) and uses P_{r-1}..: so P_i is
        // pole i - (r - 1), cyclically. The other rotations are tried too
        // (each checked by evaluation) before the curve is unperiodised.
        const std::size_t predicted = (m - static_cast<std::size_t>(g->Multiplicity(1) - 1) % m) % m;
        for (std::size_t k = 0; k < m && !ok; ++k) {
          const std::size_t shift = (predicted + k) % m;
          for (std::size_t i = 0; i < m; ++i) {
            c.points[i] = poles[(i + shift) % m];
            if (!weights.empty()) c.weights[i] = weights[(i + shift) % m];
          }
          try {
            ok = conversion_error(c, g) <= kTolerance;
          } catch (const InputError&) {
          }
        }
        if (!ok) {
          g->SetNotPeriodic();
          c.unperiodised = true;
        }
      }
      if (!g->IsPeriodic()) fill_open(c, g);
      double err = 0;
      try {
        err = conversion_error(c, g);
      } catch (const InputError& bad) {
        throw InputError(where + ": " + c.name + ": " + bad.what());
      }
      if (!(err <= kTolerance))
        throw InputError(where + ": " + c.name + ": the converted B-spline does not reproduce OpenCASCADE's curve (error " +
                         std::to_string(err) + " of its size)");
      c.name = step_curve_name(c);
      curve_of.emplace(edge.TShape().get(), out.curves.size());
      geoms.push_back(g);
      out.curves.push_back(std::move(c));
    }
    if (!shape.IsNull()) find_chains(shape, out, geoms, curve_of, tolerances, where);
    for (const StepChain& chain : out.chains)
      for (const std::size_t i : chain.curves) {
        StepCurve& c = out.curves[i];
        if (!c.curvature.empty()) continue;
        try {
          c.curvature = to_string(analyze_space(space_spline_from_json(nlohmann::json::parse(step_curve_json(c).dump()))).curvature);
        } catch (const InputError& e) {
          c.curvature = std::string("not judged (") + e.what() + ")";
        }
      }
  } catch (const Standard_Failure& f) {
    throw InputError(where + ": OpenCASCADE failed reading it (" + f.DynamicType()->Name() + ": " +
                     f.GetMessageString() + ")");
  }
  return out;
}

StepCurves read_step_curves(const std::filesystem::path& path, const ChainTolerances& chains) {
  const std::string where = path.string();
  const std::string text = read_input_file(path);  // the project's checks (exists, a file, size)
  const StepScan scan = step_scan(text);
  if (scan.depth > max_step_nesting)
    throw InputError(where + ":" + std::to_string(scan.line) + ": parentheses nest more than " +
                     std::to_string(max_step_nesting) + " deep (not read: OpenCASCADE's reader would overflow its stack)");
  if (!scan.syntax.empty())
    throw InputError(where + ":" + std::to_string(scan.syntax_line) + ": not STEP syntax: " + scan.syntax);
  if (!scan.bad_number.empty()) {
    std::string m = where;
    m.append(":").append(std::to_string(scan.bad_line)).append(": ");
    if (scan.bad_entity > 0) m.append("#").append(std::to_string(scan.bad_entity)).append(": ");
    m.append(scan.bad_number).append(" is out of range for geometry (reals up to 1e100 in magnitude, integers of 32 bits; "
             "not read: OpenCASCADE's geometry overflows on such numbers)");
    throw InputError(m);
  }
  silence_occt();
  if (const int crash = probe_crash(text, where); crash != 0)
    throw InputError(where + ": OpenCASCADE crashed reading it (" +
                     (crash > 0 ? std::string("signal ") + std::to_string(crash) : "exit " + std::to_string(-crash)) +
                     " in a child process; not read)");
  TopoDS_Shape shape;
  StepTrace trace;
  try {
    STEPControl_Reader reader;
    std::istringstream in(text);
    if (reader.ReadStream(where.c_str(), in) != IFSelect_RetDone)
      throw InputError(where + ": not a readable STEP file (OpenCASCADE's STEP reader failed)");
    refuse_failed_entities(reader, where);
    reader.TransferRoots();
    shape = reader.OneShape();
    trace = trace_of(reader);
  } catch (const Standard_Failure& f) {
    throw InputError(where + ": OpenCASCADE failed reading it (" + f.DynamicType()->Name() + ": " +
                     f.GetMessageString() + ")");
  }
  StepCurves out = shape_curves(shape, where, &trace, chains);
  if (out.curves.empty()) {
    if (out.edges == 0) throw InputError(where + ": no curves (the STEP model has no edges)");
    throw InputError(where + ": no B-spline or Bezier curves (" + std::to_string(out.edges) + " edges: " +
                     skipped_summary(out) + " skipped)");
  }
  return out;
}

namespace {

/// OpenCASCADE's curve of a converted open edge: cmr's polar knots with the
/// first and last value repeated once more are OCCT's flat knot sequence
/// (the inverse of fill_open), grouped into knots and multiplicities.
Handle(Geom_BSplineCurve) occt_curve(const StepCurve& c) {
  if (c.closed) throw InputError(step_edge_id(c) + ": a closed edge (its junctions are its own seam)");
  std::vector<double> flat;
  flat.push_back(c.knots.front());
  flat.insert(flat.end(), c.knots.begin(), c.knots.end());
  flat.push_back(c.knots.back());
  std::vector<double> knots;
  std::vector<int> mults;
  for (double k : flat) {
    if (!knots.empty() && k == knots.back()) ++mults.back();
    else knots.push_back(k), mults.push_back(1);
  }
  const int m = static_cast<int>(c.points.size()), n = static_cast<int>(knots.size());
  TColgp_Array1OfPnt poles(1, m);
  for (int i = 0; i < m; ++i) poles.SetValue(i + 1, gp_Pnt(c.points[i].x, c.points[i].y, c.points[i].z));
  TColStd_Array1OfReal k(1, n);
  TColStd_Array1OfInteger mu(1, n);
  for (int i = 0; i < n; ++i) k.SetValue(i + 1, knots[i]), mu.SetValue(i + 1, mults[i]);
  if (c.weights.empty()) return new Geom_BSplineCurve(poles, k, mu, c.degree);
  TColStd_Array1OfReal w(1, m);
  for (int i = 0; i < m; ++i) w.SetValue(i + 1, c.weights[i]);
  return new Geom_BSplineCurve(poles, w, k, mu, c.degree);
}

}  // namespace

std::vector<StepJunction> step_chain_junctions(const StepCurves& curves, const StepChain& chain,
                                               const ChainTolerances& tolerances) {
  std::vector<Handle(Geom_BSplineCurve)> g;
  try {
    for (std::size_t i : chain.curves) g.push_back(occt_curve(curves.curves[i]));
  } catch (const Standard_Failure& f) {
    throw InputError(std::string("OpenCASCADE refused a chain's edge (") + f.DynamicType()->Name() + ": " +
                     f.GetMessageString() + ")");
  }
  std::vector<StepJunction> out;
  const std::size_t n = g.size();
  for (std::size_t i = 0; i + 1 < n || (chain.closed && i < n); ++i) {
    const std::size_t k = (i + 1) % n;
    out.push_back(junction(end_of(g[i], chain.reversed[i], true), end_of(g[k], chain.reversed[k], false), tolerances));
  }
  return out;
}

}  // namespace cmr::import
