// cmr._cmr: the pybind11 module under `import cmr` (python/cmr/__init__.py,
// docs/python.md). It converts at the edge and calls the library functions
// the cmr command calls, so that every document is the command's own:
//  * Python values (dicts, lists, NumPy arrays) become the spline file's
//    JSON and go through spline_from_json / space_spline_from_json: the same
//    validation and the same one-line messages as `cmr analyze FILE`;
//  * the documents come from the command's writers (analysis_json_tree,
//    segments_json, fix_json, space_*_json) and are turned into Python
//    objects value by value (no JSON text in between);
//  * errors: cmr::InputError -> cmr.InputError (a ValueError),
//    cmr::EnvironmentError -> cmr.EnvironmentError (an OSError).
// Option names and their checks live in the Python layer (cmr/_options.py);
// this file trusts the types it is given.
//
// Long calls release the GIL. Those that may run for seconds (regions,
// fixes, reports, large analyses) run on a worker thread while the calling
// thread waits with the GIL released and checks for signals every 50 ms: a
// KeyboardInterrupt returns at once. The library has no cancellation point,
// so the abandoned computation runs to its end on its own thread, on its
// own copies of the inputs, and its result is dropped.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <cmath>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/analyze.hpp"
#include "region/contour.hpp"
#include "design/fix.hpp"
#include "design/kcurve.hpp"
#include "bezierize/knot_ops.hpp"
#include "region/region.hpp"
#include "region/region_reason.hpp"
#include "bezierize/segments.hpp"
#include "bezierize/space_analyze.hpp"
#include "design/space_fix.hpp"
#include "region/space_region.hpp"
#include "region/view_fit.hpp"
#include "draw/draw.hpp"
#include "io/font.hpp"
#include "io/output.hpp"
#include "io/ufo.hpp"
#include "report/analyze_json.hpp"
#include "report/batch.hpp"
#include "report/corpus.hpp"
#include "report/fix_json.hpp"
#include "report/gates.hpp"
#include "report/severity.hpp"
#include "report/source_fix.hpp"
#include "report/report.hpp"
#include "report/space_report.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/limits.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"
#ifdef CMR_WITH_VULKAN
#include "vk/backend_choice.hpp"
#endif

namespace py = pybind11;

namespace cmr::python {
namespace {

using Json = nlohmann::json;
using OJson = nlohmann::ordered_json;

/// A library message as the module shows it: each option field it names
/// (spline/fields.hpp) as the keyword that sets it here, where the two differ
/// (region(..., depth=) sets RegionRequest::max_depth), else by its name.
std::string python_fields(const std::string& marked) {
  static const std::map<std::string, std::string> keywords = {
      {"angle_deg", "angle_tol"}, {"curvature_rel", "curvature_tol"}, {"max_depth", "depth"},
      {"requirement", "require"}, {"with", "with_"}, {"no_severity", "severity=False"}, {"glyph_work", "work"}};
  return rename_fields(marked, [](const std::string& name) {
    const auto it = keywords.find(name);
    return it != keywords.end() ? it->second : name;
  });
}

// ------------------------------------------------------------ Python -> JSON

std::string type_name(py::handle h) { return py::type::handle_of(h).attr("__name__").cast<std::string>(); }

/// Where a value lies in an argument ("points[3][1]", "knots", "name"),
/// spelled only when an error message needs it: reading a spline from
/// Python values builds no strings on the way.
struct Where {
  const Where* parent = nullptr;
  std::string_view key;   ///< a dict member's key, or the argument's name at the top
  Py_ssize_t index = -1;  ///< a list element's index (key unused)
  std::string str() const {
    if (parent == nullptr) return std::string(key);
    std::string up = parent->str();
    if (index >= 0) return up.empty() ? std::to_string(index) : up.append("[").append(std::to_string(index)).append("]");
    return up.empty() ? std::string(key) : up.append(".").append(key);
  }
  std::string or_the_spline() const {
    std::string w = str();
    return w.empty() ? "the spline" : w;
  }
};

/// Nesting that no spline file has (they go 3 deep): deeper values are
/// refused before the reader's recursion could exhaust the stack.
constexpr int kMaxNesting = 64;

Json to_json(py::handle h, const Where& where, int depth = 0) {
  PyObject* o = h.ptr();
  if (o == Py_None) return nullptr;
  if (PyBool_Check(o)) return o == Py_True;
  if (PyFloat_Check(o)) return PyFloat_AS_DOUBLE(o);
  if (PyLong_Check(o)) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(o, &overflow);
    if (overflow == 0 && !(v == -1 && PyErr_Occurred())) return v;
    PyErr_Clear();
    return PyLong_AsDouble(o);  // beyond 64 bits: a double, as a JSON reader would
  }
  if (PyUnicode_Check(o)) {
    Py_ssize_t n = 0;
    const char* s = PyUnicode_AsUTF8AndSize(o, &n);
    if (s == nullptr) {
      PyErr_Clear();
      throw InputError(where.or_the_spline() + ": a string that is not valid Unicode");
    }
    return std::string(s, static_cast<std::size_t>(n));
  }
  const bool list = PyList_Check(o), tuple = !list && PyTuple_Check(o), dict = PyDict_Check(o);
  if ((list || tuple || dict) && depth >= kMaxNesting)
    throw InputError(where.or_the_spline() + ": nested more than " + std::to_string(kMaxNesting) +
                     " deep; a spline file's values are numbers, lists of them and strings");
  if (dict) {
    Json obj = Json::object();
    Py_ssize_t pos = 0;
    PyObject *k = nullptr, *v = nullptr;
    while (PyDict_Next(o, &pos, &k, &v)) {
      Py_ssize_t n = 0;
      const char* key = PyUnicode_Check(k) ? PyUnicode_AsUTF8AndSize(k, &n) : nullptr;
      if (key == nullptr) {
        PyErr_Clear();
        std::string shown = py::repr(k).cast<std::string>();
        const std::string up = where.str();
        throw InputError((up.empty() ? shown : up + "[" + shown + "]") +
                         (PyUnicode_Check(k) ? ": a key that is not valid Unicode" : ": a key that is not a string"));
      }
      const std::string_view name(key, static_cast<std::size_t>(n));
      obj[std::string(name)] = to_json(v, Where{&where, name}, depth + 1);
    }
    return obj;
  }
  if (list || tuple) {
    const Py_ssize_t n = list ? PyList_GET_SIZE(o) : PyTuple_GET_SIZE(o);
    Json arr = Json::array();
    arr.get_ref<Json::array_t&>().reserve(static_cast<std::size_t>(n));
    // A list may change size while its items convert (a NumPy item's
    // tolist() runs Python code): the size is read again each time.
    for (Py_ssize_t i = 0; i < (list ? PyList_GET_SIZE(o) : n); ++i) {
      const py::object item = py::reinterpret_borrow<py::object>(list ? PyList_GET_ITEM(o, i) : PyTuple_GET_ITEM(o, i));
      arr.push_back(to_json(item, Where{&where, {}, i}, depth + 1));
    }
    return arr;
  }
  if (py::isinstance<py::array>(h)) {
    const py::array a = py::reinterpret_borrow<py::array>(h);
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
      throw InputError(where.or_the_spline() + ": a NumPy array of " + py::str(a.dtype()).cast<std::string>() +
                       " is not numbers");
    return to_json(a.attr("tolist")(), where, depth);
  }
  // NumPy scalars (numpy.float64 is a float already; numpy.int64 is not an int).
  if (py::hasattr(h, "dtype") && py::hasattr(h, "item")) return to_json(h.attr("item")(), where, depth);
  throw InputError(where.or_the_spline() + ": a " + type_name(h) +
                   " is not a spline-file value (numbers, lists, NumPy arrays, dicts, strings, booleans)");
}

/// to_json of an argument named `name` ("" for a whole spline dict).
Json to_json(py::handle h, const char* name) { return to_json(h, Where{nullptr, name}); }

// ------------------------------------------------------------ JSON -> Python

py::str utf8(const std::string& s) {
  // File names that are not UTF-8 get U+FFFD, as the command's JSON does.
  PyObject* o = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace");
  if (o == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(o);
}

/// A document's object keys and its short words ("increasing", "none")
/// come from a small set (the schema's): each is made into an interned
/// Python string once and reused, so a dict costs no string creation and no
/// hashing per key. Bounded; never freed (the strings must outlive every
/// dict, and the interpreter's shutdown). Needs the GIL.
struct WordHash {
  using is_transparent = void;
  std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};
PyObject* word_by_text(std::string_view w) {
  static auto* cache = new std::unordered_map<std::string, PyObject*, WordHash, std::equal_to<>>();
  if (auto it = cache->find(w); it != cache->end()) {
    Py_INCREF(it->second);
    return it->second;
  }
  PyObject* o = PyUnicode_DecodeUTF8(w.data(), static_cast<Py_ssize_t>(w.size()), "replace");
  if (o == nullptr) throw py::error_already_set();
  if (cache->size() >= 4096 || w.size() > 64) return o;
  PyUnicode_InternInPlace(&o);
  Py_INCREF(o);  // the cache's reference
  cache->emplace(std::string(w), o);
  return o;
}

/// word_by_text behind a small table indexed by where the text lies: the
/// writers' keys and words are string literals, so each is found at its own
/// address without hashing its text (the text is still compared, so a
/// reused buffer never gets another string's word).
PyObject* word(std::string_view w) {
  struct Slot {
    const char* at = nullptr;
    std::string text;
    PyObject* word = nullptr;  // a reference owned by word_by_text's cache
  };
  static auto* slots = new std::array<Slot, 256>();
  Slot& slot = (*slots)[(reinterpret_cast<std::uintptr_t>(w.data()) >> 3 ^ w.size()) & 255];
  if (slot.at == w.data() && slot.text == w) {
    Py_INCREF(slot.word);
    return slot.word;
  }
  PyObject* o = word_by_text(w);
  if (w.size() <= 64 && PyUnicode_CHECK_INTERNED(o)) slot = {w.data(), std::string(w), o};
  return o;
}

py::object key_str(const std::string& key) { return py::reinterpret_steal<py::object>(word(key)); }

/// A document built straight into Python objects by the same writers that
/// stream the command's JSON text (report::JsonStream's interface:
/// begin_object, key, value, member, ...), e.g.
/// report::write_analysis_document: no tree and no text in between, and
/// the same keys, order and values as the command prints (a non-finite
/// number is None, as the text's null). Needs the GIL.
class PyDocument {
 public:
  void begin_object() { open(PyDict_New()); }
  void begin_array() { open(PyList_New(0)); }
  void end_object() { open_.pop_back(); }
  void end_array() { open_.pop_back(); }
  PyDocument& key(std::string_view k) {
    key_ = py::reinterpret_steal<py::object>(word(k));
    return *this;
  }
  void null() { add(Py_NewRef(Py_None)); }
  void value(bool b) { add(PyBool_FromLong(b ? 1 : 0)); }
  void value(double d) { add(std::isfinite(d) ? PyFloat_FromDouble(d) : Py_NewRef(Py_None)); }
  void value(std::string_view s) { add(s.size() <= 32 ? word(s) : utf8(std::string(s)).release().ptr()); }
  void value(const char* s) { value(std::string_view(s)); }
  void value(const std::string& s) { value(std::string_view(s)); }
  template <typename T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  void value(T v) {
    if constexpr (std::is_signed_v<T>) add(PyLong_FromLongLong(static_cast<long long>(v)));
    else add(PyLong_FromUnsignedLongLong(static_cast<unsigned long long>(v)));
  }
  template <typename T>
  void member(std::string_view k, const T& v) {
    key(k);
    value(v);
  }
  /// The finished document (after the outermost end_object / end_array).
  py::object take() { return std::move(root_); }

 private:
  // Takes the new reference `o` into the open container (or as the root).
  void add(PyObject* o) {
    if (o == nullptr) throw py::error_already_set();
    py::object owned = py::reinterpret_steal<py::object>(o);
    if (open_.empty()) {
      root_ = std::move(owned);
      return;
    }
    PyObject* parent = open_.back();
    if (PyDict_CheckExact(parent) ? PyDict_SetItem(parent, key_.ptr(), o) : PyList_Append(parent, o)) 
      throw py::error_already_set();
  }
  void open(PyObject* container) {
    add(container);                  // the parent (or root_) holds it
    open_.push_back(container);      // borrowed while open
  }

  py::object root_;
  py::object key_;
  std::vector<PyObject*> open_;
};

template <class J>
py::object to_py(const J& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.template get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.template get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.template get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: {  // a non-finite number is the text's null
      const double d = j.template get<double>();
      return std::isfinite(d) ? py::object(py::float_(d)) : py::object(py::none());
    }
    case nlohmann::json::value_t::string: return utf8(j.template get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list l(j.size());
      std::size_t i = 0;
      for (const auto& v : j) {
        py::object item = to_py(v);
        PyList_SET_ITEM(l.ptr(), static_cast<Py_ssize_t>(i++), item.release().ptr());
      }
      return l;
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it)
        if (PyDict_SetItem(d.ptr(), key_str(it.key()).ptr(), to_py(it.value()).ptr()) != 0)
          throw py::error_already_set();
      return d;
    }
    default: return py::none();
  }
}

// ------------------------------------------------------------ running

/// Runs f with the GIL released on a worker thread; the calling thread waits
/// and checks for signals (KeyboardInterrupt) every 50 ms. f must own what it
/// uses (it may outlive the call when interrupted). With `cancel` (a flag f's
/// computation reads), an interrupt sets the flag and waits for the worker
/// to stop (it throws Cancelled at its next check), so no work outlives the
/// call; without it the worker is left to finish on its own copies and its
/// result is dropped.
template <class F>
auto interruptible(F f, std::shared_ptr<std::atomic<bool>> cancel = nullptr) -> decltype(f()) {
  using R = decltype(f());
  auto task = std::make_shared<std::packaged_task<R()>>(std::move(f));
  std::future<R> result = task->get_future();
  std::thread worker([task] { (*task)(); });
  for (;;) {
    bool ready = false;
    {
      py::gil_scoped_release release;
      ready = result.wait_for(std::chrono::milliseconds(50)) == std::future_status::ready;
    }
    if (ready) break;
    if (PyErr_CheckSignals() != 0) {
      if (cancel) {
        cancel->store(true);
        py::gil_scoped_release release;
        worker.join();  // stops at the computation's next check; its Cancelled stays in the dropped future
      } else {
        worker.detach();  // it finishes on its own copies; the result is dropped
      }
      throw py::error_already_set();
    }
  }
  worker.join();
  return result.get();
}

/// interruptible(f) for a computation that takes a cancel flag: f(cancel).
template <class F>
auto cancellable(F f) -> decltype(f(static_cast<const std::atomic<bool>*>(nullptr))) {
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  return interruptible([f = std::move(f), flag = cancel]() mutable { return f(flag.get()); }, cancel);
}

/// Runs f with the GIL released on this thread (short calls).
template <class F>
auto released(F f) -> decltype(f()) {
  py::gil_scoped_release release;
  return f();
}

// ------------------------------------------------------------ splines

/// cmr.Spline: a validated planar or space spline (BSpline / SpaceSpline).
struct Spline {
  std::variant<BSpline, SpaceSpline> value;
  std::vector<std::string> point_names;  ///< the file's "point_names", kept for to_dict

  int dimension() const { return value.index() == 0 ? 2 : 3; }
  const BSpline& planar(const char* what) const {
    if (const BSpline* s = std::get_if<BSpline>(&value)) return *s;
    throw InputError(std::string(what) + ": a space curve; this is for planar splines");
  }
  const BSpline& shadow() const {
    return value.index() == 0 ? std::get<BSpline>(value) : std::get<SpaceSpline>(value).shadow();
  }
};

Spline spline_from_doc(const Json& doc) {
  Spline s = spline_dimension(doc) == 3 ? Spline{space_spline_from_json(doc), {}} : Spline{spline_from_json(doc), {}};
  if (doc.is_object() && doc.contains("point_names") && doc["point_names"].is_array())
    for (const Json& n : doc["point_names"])
      if (n.is_string()) s.point_names.push_back(n.get<std::string>());
  return s;
}

Json spline_doc(const Spline& s) {
  Json doc = s.value.index() == 0 ? spline_to_json(std::get<BSpline>(s.value))
                                  : space_spline_to_json(std::get<SpaceSpline>(s.value));
  if (!s.point_names.empty()) doc["point_names"] = s.point_names;
  return doc;
}

/// The points argument of Spline(...): a NumPy array must be N x 2 or N x 3.
Json points_json(py::handle points) {
  if (py::isinstance<py::array>(points)) {
    const py::array a = py::reinterpret_borrow<py::array>(points);
    if (a.ndim() != 2 || (a.shape(1) != 2 && a.shape(1) != 3)) {
      std::string shape = "(";
      for (py::ssize_t i = 0; i < a.ndim(); ++i) shape.append(i ? ", " : "").append(std::to_string(a.shape(i)));
      throw InputError("points: expected an N x 2 or N x 3 array, got shape " + shape + (a.ndim() == 1 ? ",)" : ")"));
    }
  }
  return to_json(points, "points");
}

Spline make_spline(py::object degree, py::object points, py::object knots, py::object weights, bool closed,
                   py::object name) {
  Json doc = Json::object();
  if (!degree.is_none()) doc["degree"] = to_json(degree, "degree");
  doc["points"] = points_json(points);
  if (!knots.is_none()) doc["knots"] = to_json(knots, "knots");
  if (!weights.is_none()) doc["weights"] = to_json(weights, "weights");
  if (closed) doc["closed"] = true;
  if (!name.is_none()) doc["name"] = to_json(name, "name");
  return spline_from_doc(doc);
}

py::array_t<double> points_array(const Spline& s) {
  const int m = s.shadow().unique_point_count(), d = s.dimension();
  py::array_t<double> a({m, d});
  auto w = a.mutable_unchecked<2>();
  for (int k = 0; k < m; ++k) {
    if (const BSpline* p = std::get_if<BSpline>(&s.value)) {
      w(k, 0) = p->points()[k].x, w(k, 1) = p->points()[k].y;
    } else {
      const Vec3& q = std::get<SpaceSpline>(s.value).points()[k];
      w(k, 0) = q.x, w(k, 1) = q.y, w(k, 2) = q.z;
    }
  }
  return a;
}

// ------------------------------------------------------------ analyze, segments

struct AnalyzeArgs {
  int depth = kDefaultDepth;
  std::vector<int> split;
  std::string mode = "cmrwi";
  std::optional<std::string> segments;
  bool each_piece = false;
  std::string each_piece_joints;
  double angle_tol = 1e-3, curvature_tol = 1e-6;
  bool torsion = false;
};

/// Spans above which an analysis runs on the worker (interruptible).
constexpr int kLongAnalysis = 256;

/// cmr analyze on a space curve (tools/cmd_space.cpp: run_space_analyze).
OJson space_analyze_doc(const SpaceSpline& space, const AnalyzeArgs& a) {
  SpaceAnalyzeOptions o;
  o.max_depth = a.depth;
  o.torsion = a.torsion;
  o.continuity = {a.angle_tol, a.curvature_tol};
  const SpaceAnalysis an = analyze_space(space, o);
  OJson segs = OJson::array(), joints = OJson::array();
  for (std::size_t i = 0; i < an.segments.size(); ++i) segs.push_back(report::space_segment_json(space, an, i));
  for (const SpaceJoint& j : an.joints) joints.push_back(report::space_joint_json(an, j));
  if (an.seam) joints.push_back(report::space_joint_json(an, *an.seam));
  return {{"segments", segs}, {"joints", joints}, {"spline", report::space_verdict_json(an)}};
}

/// As tools/cmd_analyze.cpp fills AnalyzeOptions.
AnalyzeOptions planar_analyze_options(const AnalyzeArgs& a) {
  if (a.torsion) throw InputError("a planar spline; torsion is for space curves");
  AnalyzeOptions o;
  o.classify.max_depth = a.depth;
  if (a.split.size() == 1) o.split = a.split[0];
  else o.splits = a.split;
  if (a.each_piece) {
    if (!a.split.empty()) throw InputError("each_piece takes the joints itself (each_piece=[S1, S2, ...]): drop split");
    o.each_piece = true;
    o.splits = parse_joint_list(a.each_piece_joints, "each_piece");
  }
  if (a.segments) o.segments = parse_segment_range(*a.segments, "segments");
  o.split_mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
  o.continuity = {a.angle_tol, a.curvature_tol};
  return o;
}

/// Spans up to which an analysis runs on the calling thread (not
/// interruptible: 16 cubic spans take about 40 us), the GIL held: releasing
/// and taking it back would cost a tenth of a cubic Bezier's analysis.
constexpr int kShortAnalysis = 16;

py::object analyze_py(const Spline& s, const AnalyzeArgs& a) {
  if (const SpaceSpline* space = std::get_if<SpaceSpline>(&s.value)) {
    if (!a.split.empty() || a.segments || a.mode != "cmrwi" || a.each_piece)
      throw InputError("a space curve; split, segments, each_piece and mode are for planar splines");
    const OJson doc = s.shadow().segment_count() <= kLongAnalysis
                          ? released([&] { return space_analyze_doc(*space, a); })
                          : interruptible([space = *space, a] { return space_analyze_doc(space, a); });
    return to_py(doc);
  }
  const BSpline& spline = std::get<BSpline>(s.value);
  const AnalyzeOptions o = planar_analyze_options(a);
  // The document `cmr analyze` streams (report::write_analysis_json), built
  // by the stream's own member writers straight into Python objects.
  const int n = spline.segment_count();
  const SplineAnalysis an = n <= kShortAnalysis   ? analyze(spline, o)
                            : n <= kLongAnalysis  ? released([&] { return analyze(spline, o); })
                                                  : cancellable([spline, o](const std::atomic<bool>* cancel) {
                                                     return analyze_on_threads(spline, o, 0, cancel);
                                                   });
  PyDocument doc;
  report::write_analysis_document(doc, spline, an, o.splits);
  return doc.take();
}

// ------------------------------------------------------------ regions

struct RegionArgs {
  int point = 0;
  std::vector<int> with;
  std::string mode = "cmrwi";
  std::vector<int> split;
  std::optional<std::string> segments;
  bool each_piece = false;
  std::string each_piece_joints;
  int depth = kDefaultDepth;
  int width = 512, height = 512;
  std::optional<std::vector<double>> view;
  std::string backend = "auto", precision = "fp64", device;
  bool depth_map = false, contours = false;
  std::string plane;  ///< space curves: "xy", "yz", "zx" or nine numbers (parse_space_plane); empty: the default
};

/// The backend of backend=, precision=, device= (tools/cli_common.cpp:
/// make_region_backend); its fallback note goes to `note`.
std::shared_ptr<RegionBackend> region_backend(const RegionArgs& a,
                                              const std::function<void(const std::string&)>& note) {
#ifdef CMR_WITH_VULKAN
  vk::BackendChoice choice;
  choice.kind = a.backend == "cpu" ? vk::BackendKind::cpu
                : a.backend == "auto" ? vk::BackendKind::automatic
                                      : vk::BackendKind::vulkan;
  choice.precision = a.precision == "fp32" ? vk::RegionPrecision::fp32 : vk::RegionPrecision::fp64;
  choice.device = a.device;
  return vk::make_region_backend(choice, [note](const std::string& n) {
    if (note) note(python_fields(n));  // fields as this module's keywords
  });
#else
  (void)note;
  if (a.backend == "vulkan") throw EnvironmentError("this cmr module was built without Vulkan (CMR_WITH_VULKAN=OFF)");
  return std::make_shared<CpuRegionBackend>();
#endif
}

struct RegionOut {
  RegionResult image;
  std::vector<std::uint8_t> codes;  ///< image.codes(): the PGM's bytes, handed to NumPy without a copy
  std::optional<RegionContours> contours;
  OJson summary;
  std::vector<std::string> notes;
};

/// As tools/cmd_region.cpp: region_options, validated_problems (one point;
/// without view= the fitted view, fit_region_view), render_all,
/// point_summary, contours_of, region_summary.
RegionOut region_run(const BSpline& spline, const RegionArgs& a, const std::atomic<bool>* cancel = nullptr) {
  RegionOut out;
  RegionRequest o;
  o.cancel = cancel;
  o.width = a.width;
  o.height = a.height;
  o.mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
  if (a.split.size() == 1) o.split = a.split[0];
  else o.splits = a.split;
  if (a.each_piece) {
    if (!a.split.empty()) throw InputError("each_piece takes the joints itself (each_piece=[S1, S2, ...]): drop split");
    o.each_piece = true;
    o.splits = parse_joint_list(a.each_piece_joints, "each_piece");
  }
  if (a.segments) o.segments = parse_segment_range(*a.segments, "segments");
  o.max_depth = a.depth;
  o.with = a.with;
  if (a.view) o.view = View{(*a.view)[0], (*a.view)[1], (*a.view)[2], (*a.view)[3]};
  o.depth = a.depth_map;
  o.point = a.point;
  if (spline.closed() && !o.segments && !o.split && o.splits.empty() && !o.each_piece) {
    if (const auto r = closed_support_range(spline, a.point, o.with)) {
      o.segments = r;
      out.notes.push_back("note: closed curve: P" + std::to_string(a.point) + "'s region judges the spans it acts on, " +
                          "segments " + std::to_string(r->first) + ".." + std::to_string(r->last) +
                          " (give segments= to choose others)");
    }
  }
  std::optional<RegionViewFit> fit;
  if (!o.view) o.view = (fit = fit_region_view(spline, {o}))->view;
  if (cancel != nullptr && cancel->load()) throw Cancelled();
  const RegionProblem problem = RegionProblem::make(spline, o);
  const std::shared_ptr<RegionBackend> backend =
      region_backend(a, [&out](const std::string& note) { out.notes.push_back("note: " + note); });
  // A judged span with a pole makes every position fail (cmd_region.cpp: note_poles).
  const SegmentRange range = judged_range(problem.request().segments, spline.segment_count());
  for (int i = range.first; i <= range.last; ++i)
    if (const std::vector<double> poles = segment_poles(spline, spline.segments()[i]); !poles.empty()) {
      std::ostringstream t;
      t.precision(6);
      t << poles.front();
      out.notes.push_back("note: segment " + std::to_string(i) + " has a pole (W = 0 at t = " + t.str() +
                          "): every position fails; the weights do not move with the point");
      break;
    }
  const auto t0 = std::chrono::steady_clock::now();
  out.image = backend->render(problem);
  if (cancel != nullptr && cancel->load()) throw Cancelled();  // an incomplete image: dropped
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const RegionResult& img = out.image;
  out.codes = img.codes();  // the one pass over the labels
  std::vector<std::uint64_t> counts(kSplitLabelCodes, 0);
  for (const std::uint8_t c : out.codes) ++counts[c];
  OJson c = OJson::object();
  for (int l = 0; l < img.label_codes(); ++l) c[img.label_name(static_cast<std::uint8_t>(l))] = counts[l];
  const std::uint64_t monotone = img.each_piece ? counts[1]
                                 : img.split    ? counts[1] + counts[2] + counts[3] + counts[4]
                                                : counts[1] + counts[2];
  const std::optional<std::string> why = region_reason(problem, img);
  if (monotone == 0)
    out.notes.push_back("note: P" + std::to_string(a.point) + " has no " + (a.mode == "cmr" ? "CMR" : "CMRWI") +
                        (img.split ? " with both parts monotone" : img.each_piece ? " with each piece monotone" : "") +
                        " in this view (its region is empty here" +
                        (fit && fit->empty ? std::string(", and in three times the polygon's view") : std::string()) +
                        "): " + (why ? python_fields(*why) : "see view="));
  else if (why)
    out.notes.push_back("note: " + python_fields(*why));
  if (fit && monotone > 0 && monotone * 100 < img.size())
    out.notes.push_back("note: P" + std::to_string(a.point) + "'s region is a speck: " + std::to_string(monotone) +
                        " of " + std::to_string(img.size()) +
                        " pixels (thin, or smaller than the probe's pixels; view= zooms)");
  OJson entry = {{"point", a.point}, {"counts", c}, {"seconds", seconds}, {"exact_pixels", img.exact_pixels},
                 {"exact_share", static_cast<double>(img.exact_pixels) / static_cast<double>(img.size())}};
  if (a.contours) {
    out.contours = region_contours(problem, img);
    OJson areas = OJson::object();
    for (const LabelContours& lc : out.contours->labels) areas[img.label_name(lc.label)] = lc.area;
    areas[kUndecidedBandName] = out.contours->band.area;
    entry["areas"] = areas;
  }
  const RegionRequest& r = problem.request();
  out.summary = {{"width", r.width}, {"height", r.height}, {"view", {img.view.x0, img.view.y0, img.view.x1, img.view.y1}}};
  if (fit) out.summary["view_fitted"] = fit->fitted();  // as the command: without a view only
  out.summary["mode"] = a.mode;
  out.summary["backend"] = backend->name();
  out.summary["points"] = OJson::array({entry});
  if (r.split) out.summary["split"] = *r.split;
  if (!r.splits.empty() && !r.each_piece) out.summary["split"] = r.splits;
  if (r.each_piece)
    out.summary["each_piece"] = each_piece_cuts(judged_range(r.segments, spline.segment_count()), r.splits);
  if (r.segments) {
    OJson ignored = OJson::array();
    for (int seg = 0; seg < spline.segment_count(); ++seg)
      if (seg < r.segments->first || seg > r.segments->last) ignored.push_back(seg);
    out.summary["segments"] = {r.segments->first, r.segments->last};
    out.summary["ignored_segments"] = ignored;
  }
  out.summary["seconds"] = seconds;
  return out;
}

/// The label codes as a (height, width) uint8 array (the PGM's bytes, row 0
/// at the top): the array owns the codes' vector (a capsule frees it), so the
/// labels are converted once, in the worker, and never copied.
py::array_t<std::uint8_t> label_array(std::vector<std::uint8_t>&& codes, int width, int height) {
  auto* owned = new std::vector<std::uint8_t>(std::move(codes));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<std::uint8_t>*>(p); });
  return py::array_t<std::uint8_t>({height, width}, {static_cast<py::ssize_t>(width), py::ssize_t{1}}, owned->data(),
                                   free_when_done);
}

/// A space curve's region of a point moving in a plane, on the CPU (as
/// tools/cmd_space.cpp: run_space_region with --backend cpu).
RegionOut space_region_run(const SpaceSpline& spline, const RegionArgs& a) {
  if (!a.with.empty() || !a.split.empty() || a.segments || a.each_piece || a.mode != "cmrwi" || a.contours)
    throw InputError("a space curve; with_, split, segments, each_piece, mode and contours are for planar splines");
  if (a.backend == "vulkan")
    throw InputError(
        "backend: space regions render on the CPU from Python (cmr region FILE --backend vulkan has the device)");
  SpaceRegionRequest r;
  r.point = a.point;
  if (r.point < 0 || r.point >= spline.unique_point_count())
    throw InputError("point " + std::to_string(r.point) + " is outside 0.." +
                     std::to_string(spline.unique_point_count() - 1));
  if (!a.plane.empty()) r.plane = parse_space_plane(a.plane, spline.points()[static_cast<std::size_t>(r.point)]);
  r.width = a.width;
  r.height = a.height;
  r.max_depth = a.depth;
  // Without view: the region and the moved point with a margin, as the
  // command (report::fit_space_view), with its notes.
  std::optional<report::SpaceViewFit> fit;
  if (a.view) r.view = View{(*a.view)[0], (*a.view)[1], (*a.view)[2], (*a.view)[3]};
  else r.view = (fit = report::fit_space_view(spline, r))->view;
  const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, r);
  RegionOut out;
  out.image = problem.render();
  const RegionResult& img = out.image;
  out.codes = img.codes();
  std::uint64_t counts[kRegionLabelCodes] = {}, inside = 0;
  for (const std::uint8_t c : out.codes) ++counts[c];
  for (std::size_t i = 0; i < img.size(); ++i) inside += img.in_region(i) ? 1 : 0;
  if (fit && fit->empty)
    out.notes.push_back("note: P" + std::to_string(r.point) +
                        " has no region near the curve in this plane (the view is the curve's)");
  else if (fit && inside * 100 < img.size())
    out.notes.push_back("note: P" + std::to_string(r.point) + "'s region is a speck: " + std::to_string(inside) +
                        " of " + std::to_string(img.size()) + " pixels, far from the point or thin (view= zooms)");
  OJson c;
  for (std::uint8_t l = 0; l < kRegionLabelCodes; ++l) c[img.label_name(l)] = counts[l];
  const SpacePlane& plane = *problem.request().plane;
  auto vec3 = [](const Vec3& p) { return OJson{p.x, p.y, p.z}; };
  out.summary = {{"width", img.width},
                 {"height", img.height},
                 {"view", {img.view.x0, img.view.y0, img.view.x1, img.view.y1}},
                 {"plane", {{"origin", vec3(plane.origin)}, {"u", vec3(plane.u)}, {"v", vec3(plane.v)}}},
                 {"dimension", 3},
                 {"backend", "cpu"},
                 {"point", r.point},
                 {"view_fitted", fit.has_value()},
                 {"plane_name", report::space_plane_name(spline, plane, r.point)},
                 {"counts", c},
                 {"seconds", img.seconds},
                 {"exact_pixels", img.exact_pixels}};
  return out;
}

py::object region_py(const Spline& s, const RegionArgs& a, bool full) {
  if (const SpaceSpline* space = std::get_if<SpaceSpline>(&s.value)) {
    const SpaceSpline curve = *space;
    auto out = std::make_shared<RegionOut>(interruptible([curve, a] { return space_region_run(curve, a); }));
    py::array_t<std::uint8_t> labels = label_array(std::move(out->codes), out->image.width, out->image.height);
    py::list notes;
    for (const std::string& n : out->notes) notes.append(utf8(n));
    if (!full) return py::make_tuple(labels, notes);
    py::dict r;
    r["labels"] = labels;
    r["summary"] = to_py(out->summary);
    r["counts"] = to_py(out->summary["counts"]);
    r["notes"] = notes;
    if (a.depth_map) {
      py::array_t<std::uint8_t> depth({out->image.height, out->image.width});
      std::copy(out->image.depth.begin(), out->image.depth.end(), depth.mutable_data());
      r["depth"] = depth;
    }
    return r;
  }
  if (!a.plane.empty()) throw InputError("plane is for space curves (this spline is planar)");
  const BSpline spline = s.planar("region");
  auto out = std::make_shared<RegionOut>(
      cancellable([spline, a](const std::atomic<bool>* cancel) { return region_run(spline, a, cancel); }));
  py::array_t<std::uint8_t> labels = label_array(std::move(out->codes), out->image.width, out->image.height);
  if (!full) {
    py::list notes;
    for (const std::string& n : out->notes) notes.append(utf8(n));
    return py::make_tuple(labels, notes);
  }
  py::dict r;
  r["labels"] = labels;
  r["summary"] = to_py(out->summary);
  r["counts"] = to_py(out->summary["points"][0]["counts"]);
  if (out->contours) r["areas"] = to_py(out->summary["points"][0]["areas"]);
  py::list notes;
  for (const std::string& n : out->notes) notes.append(utf8(n));
  r["notes"] = notes;
  if (a.depth_map) {
    py::array_t<std::uint8_t> depth({out->image.height, out->image.width});
    std::copy(out->image.depth.begin(), out->image.depth.end(), depth.mutable_data());
    r["depth"] = depth;
  }
  if (out->contours) {
    // Per label: its outlines as (n, 2) float arrays (counter-clockwise around
    // regions, clockwise around holes) and its area.
    py::dict contours;
    auto outlines = [](const LabelContours& lc) {
      py::list loops;
      for (const std::vector<int>& loop : lc.outlines) {
        py::array_t<double> xy({static_cast<py::ssize_t>(loop.size()), py::ssize_t{2}});
        auto w = xy.mutable_unchecked<2>();
        for (std::size_t i = 0; i < loop.size(); ++i)
          w(i, 0) = lc.vertices[loop[i]].x, w(i, 1) = lc.vertices[loop[i]].y;
        loops.append(xy);
      }
      return loops;
    };
    for (const LabelContours& lc : out->contours->labels) contours[utf8(out->image.label_name(lc.label))] = outlines(lc);
    contours[kUndecidedBandName] = outlines(out->contours->band);
    r["contours"] = contours;
  }
  return r;
}

// ------------------------------------------------------------ fix_glyph

/// cmr.fix_glyph: a font source's glyph fixed for every required check on
/// the grid, as tools/cmd_fix.cpp's run_source_fix does for `cmr fix
/// FONT.ufo --glyph NAME` (the same library calls and document; in_place
/// writes the .glif as --in-place does: only the moved points' x and y, and
/// with add_nodes the added points).
py::object fix_glyph_py(const std::string& file, const std::string& glyph, const std::string& require, double grid,
                        double max_move, const std::vector<std::string>& points, int depth, bool in_place, long work,
                        bool add_nodes) {
  report::GlyphFixOptions o = report::source_fix_options(require, depth, grid, max_move, work);
  o.add_nodes = add_nodes;
  report::SourceFix f = interruptible([file, glyph, points, o] { return report::fix_source_glyph(file, glyph, points, o); });
  show_fields_in(f.contours, python_fields);
  if (!f.failed.empty()) throw InputError(file + ": " + python_fields(f.failed));
  OJson doc = {{"file", file}, {"glyph", f.glyph.name}, {"require", require}, {"grid", grid}, {"contours", f.contours}};
  if (!f.points.empty()) doc["points"] = f.points;
  if (in_place) {
    OutputSet outputs;
    if (!f.edits.empty())
      outputs.stage(f.glyph.source, import::rewrite_glif_points(read_input_file(f.glyph.source), f.edits, f.glyph.source));
    outputs.commit();
    doc["written"] = f.glyph.source;
  }
  return to_py(doc);
}

/// cmr.fix_glyphs: each selected glyph of a UFO that fails fixed on its
/// own, as `cmr fix FONT.ufo --glyphs SPEC` does (report/source_fix.hpp:
/// the same library calls and document); in_place writes the fixed
/// glyphs' .glif files together (all or none), as --in-place does.
py::object fix_glyphs_py(const std::string& file, const std::string& glyphs, const std::string& require, double grid,
                         double max_move, int depth, double min_severity, bool in_place, long work, bool add_nodes) {
  report::GlyphFixOptions o = report::source_fix_options(require, depth, grid, max_move, work);
  o.add_nodes = add_nodes;
  const import::GlyphSelection which = import::parse_glyph_selection(glyphs);
  report::SourceGlyphsOutput r = interruptible([file, which, o, require, grid, min_severity] {
    return report::source_glyphs_output(report::fix_source_glyphs(file, which, o, min_severity, 0), file, require,
                                        grid);
  });
  show_fields_in(r.doc, python_fields);
  if (in_place) {
    OutputSet outputs;
    OJson written = OJson::array();
    for (const auto& [glif, text] : r.changed) {
      outputs.stage(glif, text);
      written.push_back(glif);
    }
    outputs.commit();
    r.doc["written"] = written;
  }
  return to_py(r.doc);
}

// ------------------------------------------------------------ fix

struct FixArgs {
  std::string require = "cmr";
  std::vector<int> points;
  std::string keep = "g1";
  std::optional<std::string> segments;
  double max_move = 0, tolerance = 1e-6;
  int depth = kDefaultDepth;
  int grid = 32;
  std::string plane;  ///< space curves: --plane (xy, yz, zx or nine numbers)
};

/// A space curve's fix (as tools/cmd_space_fix.cpp: run_space_fix).
py::object space_fix_py(const Spline& s, const FixArgs& a) {
  if (a.segments) throw InputError("a space curve; segments is for planar splines");
  if (a.require != "cmr" && a.require != "cmrwi")
    throw InputError("a space curve; its fix takes require cmr (|kappa| monotone, no zero curvature) or cmrwi "
                     "(|kappa| monotone), not '" + a.require + "'");
  SpaceFixRequest request;
  request.no_zero_curvature = a.require == "cmr";
  request.points = a.points;
  request.plane_text = a.plane;
  request.keep = a.keep == "g2" ? Keep::g2 : a.keep == "none" ? Keep::none : Keep::g1;
  request.max_move = a.max_move;
  request.tolerance = a.tolerance;
  request.max_depth = a.depth;
  const SpaceSpline spline = std::get<SpaceSpline>(s.value);
  const SpaceFixResult f = interruptible([spline, request] { return space_fix(spline, request); });
  if (!f.fixed) throw InputError((spline.name().empty() ? "" : spline.name() + ": ") + python_fields(f.reason));
  Spline fixed{*f.spline, s.point_names};
  OJson doc = report::space_fix_document(std::nullopt, a.require, request, f);
  show_fields_in(doc, python_fields);  // the units' reasons name fields
  return py::make_tuple(fixed, to_py(doc));
}

py::object fix_py(const Spline& s, const FixArgs& a) {
  if (!(a.max_move >= 0) || !std::isfinite(a.max_move))
    throw InputError("max_move: " + std::to_string(a.max_move) + " is not a distance >= 0");
  if (s.dimension() == 3) return space_fix_py(s, a);
  if (!a.plane.empty()) throw InputError("plane is for space curves (this spline is planar)");
  const BSpline spline = s.planar("fix");
  // As tools/cmd_fix.cpp fills FixRequest.
  FixRequest request;
  request.requirement = parse_fix_requirement(a.require);
  if (a.segments) request.requirement.segments = parse_segment_range(*a.segments, "segments");
  request.points = a.points;
  request.together = request.points.size() > 1;
  request.keep = a.keep == "g2" ? Keep::g2 : a.keep == "none" ? Keep::none : Keep::g1;
  request.max_move = a.max_move;
  request.tolerance = a.tolerance;
  request.max_depth = a.depth;
  request.grid = a.grid;
  const FixResult f = cancellable([spline, request](const std::atomic<bool>* cancel) mutable {
    request.cancel = cancel;
    return fix(spline, request);
  });
  if (!f.fixed) throw InputError((spline.name().empty() ? "" : spline.name() + ": ") + python_fields(f.reason));
  Spline fixed{*f.spline, s.point_names};
  return py::make_tuple(fixed, to_py(report::fix_json(std::nullopt, request, f)));
}

// ------------------------------------------------------------ knots, kcurve

Spline knots_op(const Spline& s, const std::string& op, double u, int times, std::optional<double> tol, int index) {
  const BSpline& spline = s.planar("knots");
  // As tools/cmd_knots.cpp: apply().
  const BSpline result = released([&]() -> BSpline {
    if (op == "insert") return insert_knot(spline, u, times);
    if (op == "remove") return remove_knot(spline, u, tol.value_or(kRemovalRelativeTolerance * extent(spline))).spline;
    if (op == "set") return set_knot(spline, index, u);
    if (op == "clamp") return clamp(spline);
    if (op == "uniform") return make_uniform(spline);
    if (op == "elevate") return elevate_degree(spline);
    if (op == "refine") return refine(spline);
    throw InputError("knots: unknown operation '" + op + "' (insert, remove, set, clamp, uniform, elevate, refine)");
  });
  return Spline{result, {}};
}

py::object kcurve_py(py::handle points, bool closed, bool cubic, double tolerance, int max_iterations) {
  // The points file's checks (tools/cmd_kcurve.cpp: kcurve_points_from_json).
  const Json pts = points_json(points);
  if (!pts.is_array()) throw InputError("points: not an array of [x, y] pairs");
  std::vector<Vec2> input;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    if (!pts[i].is_array() || pts[i].size() != 2) throw InputError(where + " is not an [x, y] pair");
    for (int c = 0; c < 2; ++c) {
      if (!pts[i][c].is_number()) throw InputError(where + "[" + std::to_string(c) + "] is not a number");
      if (!std::isfinite(pts[i][c].get<double>()))
        throw InputError(where + "[" + std::to_string(c) + "] is not a finite number");
    }
    input.emplace_back(pts[i][0].get<double>(), pts[i][1].get<double>());
  }
  KCurveOptions options;
  options.closed = closed;
  options.tolerance = tolerance;
  options.max_iterations = max_iterations;
  const KCurve curve = cancellable([input, options](const std::atomic<bool>* cancel) mutable {
    options.cancel = cancel;
    return kcurve(input, options);
  });
  // The command's two refusals, in its words (without the file name).
  if (!curve.converged()) {
    std::ostringstream why;
    why << "the kappa-curve did not converge in " << curve.iterations << " iterations (residual " << curve.residual
        << " > tolerance " << curve.tolerance
        << "); very sharp turns and nearly collinear points converge slowly: spread the points or raise tolerance";
    throw InputError(why.str());
  }
  if (cubic) {
    const std::vector<int> uncertified = kcurve_cubic_uncertified(curve);
    if (!uncertified.empty())
      throw InputError("piece " + std::to_string(uncertified.front()) +
                       " of the cubic chain could not be certified monotone (its curvature maximum is not on a joint)");
  }
  py::list notes;
  for (const std::string& line : kcurve_off_point_notes(curve, input)) notes.append(utf8("note: " + line));
  const BSpline spline = cubic ? kcurve_cubic_chain(curve) : kcurve_quadratic_spline(curve);
  return py::make_tuple(Spline{spline, {}}, notes);
}

// ------------------------------------------------------------ report

struct ReportArgs {
  std::vector<std::string> files;
  std::string out;
  std::string require;
  std::optional<std::string> segments;
  int depth = kDefaultDepth;
  bool thumbnails = false;
  bool fixes = false;
  bool cache = true;
  std::string glyphs = "A-Z,a-z";
  std::string location;  ///< a variable font's instance, "wght=700,opsz=14" (empty: the default)
  std::string between;  ///< interpolation gates: "wght=400:wght=700" (empty: between adjacent masters)
  std::optional<double> min_severity;  ///< as --min-severity (none: fonts get the default)
  bool severity = true, strict = false;  ///< severity false: --no-severity
  double angle_tol = 1e-3, curvature_tol = 1e-6;
  std::string backend = "cpu";
};

py::object report_py(const ReportArgs& a) {
  // As tools/cmd_report.cpp (planar files: spline files, SVG files, fonts).
  ContinuityTolerances continuity{a.angle_tol, a.curvature_tol};
  validate(continuity);
  report::ReportOptions o;
  o.show_fields = python_fields;
  o.continuity = continuity;
  if (!a.require.empty()) report::parse_require_list(a.require, o);
  if (a.segments) o.segments = parse_segment_range(*a.segments, "segments");
  report::set_severity_options(o, a.min_severity, a.severity, a.strict);  // fonts: severity by default, as the command
  o.max_depth = a.depth;
  o.regions = a.thumbnails;
  RegionArgs ra;
  ra.backend = a.backend;
  o.backend = region_backend(ra, [](const std::string&) {});  // the CPU backend by default: no note
  report::BatchOptions b;
  report::select_font_inputs(b, o, a.glyphs, a.location, a.between, a.files);
  b.out = a.out;
  b.fixes = a.fixes;
  b.cache = a.cache;
  b.report = std::move(o);
  const bool interpolation = std::any_of(b.report.gates.begin(), b.report.gates.end(), report::is_interpolation_gate);
  const std::vector<std::string> files = report::collect_run_files(a.files, {}, interpolation, &b.bases, &b.skipped);
  const report::BatchSummary s = interruptible([files, b] { return report::run_batch(files, b); });
  py::dict r;
  r["exit_code"] = s.exit_code;
  r["summary"] = utf8(report::summary_line(s));
  py::list invalid;
  for (const std::string& e : s.invalid_messages) invalid.append(utf8(e));
  r["invalid"] = invalid;
  r["pass"] = s.pass, r["fail"] = s.fail, r["items"] = s.items, r["findings"] = s.findings;
  return r;
}

/// One spline judged as `cmr report` judges it, without regions or fixes
/// (report/batch.hpp: judged_report): its entry of the cmr-report/2
/// document (docs/report-schema.md), the gates' violations included.
py::object judge_py(const Spline& s, const std::string& require, int depth, double angle_tol, double curvature_tol) {
  const BSpline spline = s.planar("judge");
  report::ReportOptions o;
  o.show_fields = python_fields;
  o.continuity = ContinuityTolerances{angle_tol, curvature_tol};
  validate(o.continuity);
  if (!require.empty()) report::parse_require_list(require, o);
  o.max_depth = depth;
  o.regions = false;
  OJson doc = released([&] {
    const report::SplineReport r = report::judged_report(spline, o);
    return report::report_json({r}, o);
  });
  return to_py(doc["splines"][0]);
}

/// Entries of judge_many's list for some reports.
void append_judged(py::list& out, const std::vector<report::SplineReport>& reports) {
  for (const report::SplineReport& r : reports) {
    OJson entry = {{"name", r.name}, {"status", report::status_word(r)}};
    if (!r.error.empty()) entry["error"] = r.error;
    if (!r.gates.empty()) entry["gates"] = report::gates_json(r);
    out.append(to_py(entry));
  }
}

/// Many splines judged as `cmr report` judges them (report_batch: every
/// core, no regions, no fixes): per spline {"name", "status", "gates"} with
/// report.json's gates (report::gates_json).
py::object judge_many_py(const std::vector<Spline>& splines, const std::string& require, int depth, int threads) {
  report::ReportOptions o;
  o.show_fields = python_fields;
  if (!require.empty()) report::parse_require_list(require, o);
  o.max_depth = depth;
  o.regions = false;
  o.threads = threads;
  std::vector<report::ReportInput> inputs;
  inputs.reserve(splines.size());
  for (const Spline& s : splines) inputs.push_back({s.shadow().name(), s.planar("judge_many"), {}});
  const std::vector<report::SplineReport> reports =
      interruptible([inputs = std::move(inputs), o]() mutable { return report::report_batch(std::move(inputs), o); });
  py::list out;
  append_judged(out, reports);
  return out;
}

/// cmr.JudgeQueue: judge_many in the background, so that Python can draw
/// the next glyphs while the batches before them are judged. One worker
/// thread takes the submitted batches in order and runs report_batch on
/// each (on `threads` threads, the same judging as judge_many); results()
/// waits, with the GIL released and signals checked every 50 ms, and
/// returns every entry submitted so far, in submission order.
/// A KeyboardInterrupt in results() drops the batches not yet started (the
/// one running finishes on its own copies and is dropped too). The worker
/// owns the shared state, so the queue may be dropped at any time.
class JudgeQueue {
 public:
  JudgeQueue(const std::string& require, int depth, int threads) : state_(std::make_shared<State>()) {
    if (!require.empty()) report::parse_require_list(require, state_->options);
    state_->options.max_depth = depth;
    state_->options.regions = false;
    state_->options.threads = threads;
    worker_ = std::thread([st = state_] { run(*st); });
  }
  JudgeQueue(const JudgeQueue&) = delete;
  JudgeQueue& operator=(const JudgeQueue&) = delete;
  ~JudgeQueue() {
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      state_->stop = true;
      state_->todo.clear();
    }
    state_->wake.notify_all();
    worker_.detach();  // finishes a running batch on its own copies, then ends
  }

  void submit(const std::vector<Spline>& splines) {
    std::vector<report::ReportInput> inputs;
    inputs.reserve(splines.size());
    for (const Spline& s : splines) inputs.push_back({s.shadow().name(), s.planar("JudgeQueue.submit"), {}});
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      state_->todo.push_back(std::move(inputs));
      ++state_->submitted;
    }
    state_->wake.notify_all();
  }

  py::list results() {
    for (;;) {
      bool finished = false;
      {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(state_->mutex);
        finished = state_->done.wait_for(lock, std::chrono::milliseconds(50), [&] {
          return state_->judged == state_->submitted || state_->error;
        });
      }
      if (finished) break;
      if (PyErr_CheckSignals() != 0) {
        std::lock_guard<std::mutex> lock(state_->mutex);
        state_->submitted -= state_->todo.size();
        state_->todo.clear();
        throw py::error_already_set();
      }
    }
    std::vector<std::vector<report::SplineReport>> batches;
    {
      std::lock_guard<std::mutex> lock(state_->mutex);
      if (state_->error) std::rethrow_exception(std::exchange(state_->error, nullptr));
      batches.swap(state_->reports);
    }
    for (auto& b : batches) pending_.push_back(std::move(b));
    py::list out;
    for (const auto& b : pending_) append_judged(out, b);
    return out;
  }

 private:
  struct State {
    report::ReportOptions options;
    std::mutex mutex;
    std::condition_variable wake, done;
    std::deque<std::vector<report::ReportInput>> todo;
    std::vector<std::vector<report::SplineReport>> reports;  // judged, not yet taken by results()
    std::size_t submitted = 0, judged = 0;
    std::exception_ptr error;
    bool stop = false;
  };

  static void run(State& st) {
    std::unique_lock<std::mutex> lock(st.mutex);
    for (;;) {
      st.wake.wait(lock, [&] { return st.stop || !st.todo.empty(); });
      if (st.todo.empty()) return;  // stopped
      std::vector<report::ReportInput> batch = std::move(st.todo.front());
      st.todo.pop_front();
      const report::ReportOptions options = st.options;
      lock.unlock();
      std::vector<report::SplineReport> judged;
      std::exception_ptr error;
      try {
        judged = report::report_batch(std::move(batch), options);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      if (error && !st.error) st.error = error;
      st.reports.push_back(std::move(judged));
      ++st.judged;
      st.done.notify_all();
    }
  }

  std::shared_ptr<State> state_;
  std::thread worker_;
  std::vector<std::vector<report::SplineReport>> pending_;  // taken by an earlier results()
};

// ------------------------------------------------------------ fonts

/// One contour of the pen (python/cmr/pen.py) through io/font.cpp's builder:
/// the spline of `cmr import` with its point names (to_dict() is the file
/// `cmr import` writes), or None for a contour without a piece.
py::object font_contour(py::array_t<double, py::array::c_style | py::array::forcecast> xy, const std::string& tags,
                        int contour, int degree, const std::string& glyph) {
  if (xy.ndim() != 2 || xy.shape(1) != 2 || static_cast<std::size_t>(xy.shape(0)) != tags.size())
    throw InputError("font contour: expected N x 2 points and N tags");
  if (degree != 2 && degree != 3) throw InputError("font contour: degree " + std::to_string(degree) + " is not 2 or 3");
  std::vector<import::OutlinePoint> outline(tags.size());
  auto r = xy.unchecked<2>();
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const char t = tags[i];
    if (t != 'o' && t != 'q' && t != 'c') throw InputError("font contour: tag '" + std::string(1, t) + "' is not o, q or c");
    outline[i] = {{r(i, 0), r(i, 1)},
                  t == 'o' ? import::OutlinePoint::Tag::on
                  : t == 'q' ? import::OutlinePoint::Tag::conic
                             : import::OutlinePoint::Tag::cubic};
  }
  std::optional<import::Contour> c = import::outline_contour(outline, contour, degree, glyph, import::PointNaming::editor);
  if (!c) return py::none();
  return py::cast(Spline{std::move(c->spline), std::move(c->point_names)});
}

}  // namespace
}  // namespace cmr::python

PYBIND11_MODULE(_cmr, m) {
  using namespace cmr;
  using namespace cmr::python;
  m.doc() = "cmr's C++ library (see the cmr package and docs/python.md)";
  // cmr::InputError and cmr::EnvironmentError (and the backends' errors
  // derived from it) with their one-line messages.
  static PyObject* input_error = py::register_exception<InputError>(m, "InputError", PyExc_ValueError).ptr();
  static PyObject* environment_error =
      py::register_exception<EnvironmentError>(m, "EnvironmentError", PyExc_OSError).ptr();
  // Their messages with the option fields they name (spline/fields.hpp) as
  // this module's keywords (python_fields); tried before the two above.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error, python_fields(marked_text(e)).c_str());
    } catch (const EnvironmentError& e) {
      PyErr_SetString(environment_error, python_fields(marked_text(e)).c_str());
    }
  });

  py::class_<Spline>(m, "Spline")
      .def(py::init(&make_spline), py::arg("degree"), py::arg("points"), py::arg("knots") = py::none(),
           py::arg("weights") = py::none(), py::arg("closed") = false, py::arg("name") = py::none())
      .def_static("from_dict", [](py::handle d) { return spline_from_doc(to_json(d, "")); })
      .def_static("load",
                  [](const std::string& path) {
                    try {
                      return spline_from_doc(read_spline_document(path));
                    } catch (const InputError& e) {
                      const std::string what = e.what();
                      if (what.rfind(path + ":", 0) == 0) throw;
                      throw InputFieldError(path + ": " + marked_text(e));
                    }
                  })
      .def("to_dict", [](const Spline& s) { return to_py(spline_doc(s)); })
      .def_property_readonly("degree", [](const Spline& s) { return s.shadow().degree(); })
      .def_property_readonly("dimension", &Spline::dimension)
      .def_property_readonly("closed", [](const Spline& s) { return s.shadow().closed(); })
      .def_property_readonly("name", [](const Spline& s) { return s.shadow().name(); })
      .def_property_readonly("knots", [](const Spline& s) { return s.shadow().period_knots(); })
      .def_property_readonly("points", &points_array)
      .def_property_readonly("weights",
                             [](const Spline& s) -> py::object {
                               const BSpline& b = s.shadow();
                               if (!b.is_rational()) return py::none();
                               return py::cast(std::vector<double>(b.weights().begin(),
                                                                   b.weights().begin() + b.unique_point_count()));
                             })
      .def_property_readonly("point_names", [](const Spline& s) { return s.point_names; })
      .def_property_readonly("segment_count", [](const Spline& s) { return s.shadow().segment_count(); })
      .def_property_readonly("domain", [](const Spline& s) {
        return py::make_tuple(s.shadow().domain_begin(), s.shadow().domain_end());
      })
      .def_property_readonly("segment_intervals", [](const Spline& s) {
        std::vector<std::pair<double, double>> v;
        for (const Segment& seg : s.shadow().segments()) v.emplace_back(seg.a, seg.b);
        return v;
      })
      .def("evaluate",
           [](const Spline& s, py::array_t<double, py::array::forcecast> t) {
             const BSpline& b = s.planar("evaluate");
             auto ts = t.unchecked<1>();
             py::array_t<double> out({ts.shape(0), py::ssize_t{2}});
             auto w = out.mutable_unchecked<2>();
             for (py::ssize_t i = 0; i < ts.shape(0); ++i) {
               const Vec2 p = evaluate(b, ts(i));
               w(i, 0) = p.x, w(i, 1) = p.y;
             }
             return out;
           },
           py::arg("t"), "C(t) at each parameter of a 1-D array: an (n, 2) array")
      .def("derivative",
           [](const Spline& s, py::array_t<double, py::array::forcecast> t, int r) {
             const BSpline& b = s.planar("derivative");
             if (r < 0 || r > b.degree())
               throw InputError("derivative: order " + std::to_string(r) + " is outside 0.." + std::to_string(b.degree()));
             auto ts = t.unchecked<1>();
             py::array_t<double> out({ts.shape(0), py::ssize_t{2}});
             auto w = out.mutable_unchecked<2>();
             for (py::ssize_t i = 0; i < ts.shape(0); ++i) {
               const Vec2 p = derivative(b, ts(i), r);
               w(i, 0) = p.x, w(i, 1) = p.y;
             }
             return out;
           },
           py::arg("t"), py::arg("r") = 1, "the r-th derivative C^(r)(t) at each parameter: an (n, 2) array")
      .def("curvature",
           [](const Spline& s, py::array_t<double, py::array::forcecast> t) {
             const BSpline& b = s.planar("curvature");
             auto ts = t.unchecked<1>();
             py::array_t<double> out(ts.shape(0));
             auto w = out.mutable_unchecked<1>();
             for (py::ssize_t i = 0; i < ts.shape(0); ++i) w(i) = curvature(b, ts(i));
             return out;
           },
           py::arg("t"), "signed curvature at each parameter of a 1-D array")
      .def("__repr__", [](const Spline& s) {
        const BSpline& b = s.shadow();
        return "cmr.Spline(degree=" + std::to_string(b.degree()) + ", points=" + std::to_string(b.unique_point_count()) +
               " x " + std::to_string(s.dimension()) + ", segments=" + std::to_string(b.segment_count()) +
               (b.closed() ? ", closed" : "") + (b.is_rational() ? ", rational" : "") +
               (b.name().empty() ? "" : ", name=" + b.name()) + ")";
      });

  py::class_<AnalyzeArgs>(m, "_AnalyzeArgs")
      .def(py::init<>())
      .def_readwrite("depth", &AnalyzeArgs::depth)
      .def_readwrite("split", &AnalyzeArgs::split)
      .def_readwrite("mode", &AnalyzeArgs::mode)
      .def_readwrite("segments", &AnalyzeArgs::segments)
      .def_readwrite("each_piece", &AnalyzeArgs::each_piece)
      .def_readwrite("each_piece_joints", &AnalyzeArgs::each_piece_joints)
      .def_readwrite("angle_tol", &AnalyzeArgs::angle_tol)
      .def_readwrite("curvature_tol", &AnalyzeArgs::curvature_tol)
      .def_readwrite("torsion", &AnalyzeArgs::torsion);
  m.def("_analyze", &analyze_py);
  m.def("_segments", [](const Spline& s) {
    const BSpline& b = s.planar("segments");
    return to_py(released([&] { return report::segments_json(b); }));
  });

  py::class_<RegionArgs>(m, "_RegionArgs")
      .def(py::init<>())
      .def_readwrite("point", &RegionArgs::point)
      .def_readwrite("with_", &RegionArgs::with)
      .def_readwrite("mode", &RegionArgs::mode)
      .def_readwrite("split", &RegionArgs::split)
      .def_readwrite("segments", &RegionArgs::segments)
      .def_readwrite("each_piece", &RegionArgs::each_piece)
      .def_readwrite("each_piece_joints", &RegionArgs::each_piece_joints)
      .def_readwrite("depth", &RegionArgs::depth)
      .def_readwrite("width", &RegionArgs::width)
      .def_readwrite("height", &RegionArgs::height)
      .def_readwrite("view", &RegionArgs::view)
      .def_readwrite("backend", &RegionArgs::backend)
      .def_readwrite("precision", &RegionArgs::precision)
      .def_readwrite("device", &RegionArgs::device)
      .def_readwrite("depth_map", &RegionArgs::depth_map)
      .def_readwrite("contours", &RegionArgs::contours)
      .def_readwrite("plane", &RegionArgs::plane);
  m.def("_region", &region_py);

  py::class_<FixArgs>(m, "_FixArgs")
      .def(py::init<>())
      .def_readwrite("require", &FixArgs::require)
      .def_readwrite("points", &FixArgs::points)
      .def_readwrite("keep", &FixArgs::keep)
      .def_readwrite("segments", &FixArgs::segments)
      .def_readwrite("max_move", &FixArgs::max_move)
      .def_readwrite("tolerance", &FixArgs::tolerance)
      .def_readwrite("depth", &FixArgs::depth)
      .def_readwrite("grid", &FixArgs::grid)
      .def_readwrite("plane", &FixArgs::plane);
  m.def("_fix", &fix_py);
  m.def("_fix_glyph", &fix_glyph_py);
  m.def("_fix_glyphs", &fix_glyphs_py);

  m.def("_knots", &knots_op);
  m.def("_kcurve", &kcurve_py);

  py::class_<ReportArgs>(m, "_ReportArgs")
      .def(py::init<>())
      .def_readwrite("files", &ReportArgs::files)
      .def_readwrite("out", &ReportArgs::out)
      .def_readwrite("require", &ReportArgs::require)
      .def_readwrite("segments", &ReportArgs::segments)
      .def_readwrite("depth", &ReportArgs::depth)
      .def_readwrite("thumbnails", &ReportArgs::thumbnails)
      .def_readwrite("fixes", &ReportArgs::fixes)
      .def_readwrite("cache", &ReportArgs::cache)
      .def_readwrite("glyphs", &ReportArgs::glyphs)
      .def_readwrite("location", &ReportArgs::location)
      .def_readwrite("between", &ReportArgs::between)
      .def_readwrite("min_severity", &ReportArgs::min_severity)
      .def_readwrite("severity", &ReportArgs::severity)
      .def_readwrite("strict", &ReportArgs::strict)
      .def_readwrite("angle_tol", &ReportArgs::angle_tol)
      .def_readwrite("curvature_tol", &ReportArgs::curvature_tol)
      .def_readwrite("backend", &ReportArgs::backend);
  m.def("_report", &report_py);
  m.def("_judge", &judge_py);
  m.def("_judge_many", &judge_many_py);
  py::class_<JudgeQueue>(m, "_JudgeQueue")
      .def(py::init<const std::string&, int, int>())
      .def("submit", &JudgeQueue::submit)
      .def("results", &JudgeQueue::results);
  m.def("_analyze_default", [](py::handle s) {
    // cmr.analyze(spline) with every option at its default: no options to
    // convert. A cmr.Spline or a spline-file dict (cmr.Spline.from_dict).
    if (PyDict_Check(s.ptr())) return analyze_py(spline_from_doc(to_json(s, "")), AnalyzeArgs{});
    return analyze_py(s.cast<const Spline&>(), AnalyzeArgs{});
  });

  m.def("_font_contour", &font_contour);
  m.def("_label_colour", [](int label, bool split) {
    // The legend's colour of a plain (Direction) or split label code (draw/draw.hpp).
    const draw::Rgb c = draw::label_colour(static_cast<std::uint8_t>(label), split);
    return py::make_tuple(c.r, c.g, c.b);
  });
  m.def("_time_analyze",
        [](const Spline& s, int n, bool document, bool read) {
          // The C++ side of tools/bench/python_overhead.py: n calls of
          // analyze() (with `document`, and analysis_json_tree; with `read`,
          // after reading the spline from its spline-file JSON tree, the
          // C++ counterpart of a dict argument), no Python.
          const BSpline& b = s.planar("_time_analyze");
          const Json doc = spline_to_json(b);
          py::gil_scoped_release release;
          std::size_t sink = 0;
          const auto t0 = std::chrono::steady_clock::now();
          for (int i = 0; i < n; ++i) {
            const SplineAnalysis a = read ? analyze(spline_from_json(doc), AnalyzeOptions{}) : analyze(b, AnalyzeOptions{});
            sink += a.segments.size();
            if (document) sink += report::analysis_json_tree(b, a, {}).size();
          }
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          return sink > 0 ? seconds : -seconds;
        },
        py::arg("spline"), py::arg("n"), py::arg("document") = false, py::arg("read") = false);
  m.attr("kDefaultDepth") = kDefaultDepth;
  m.attr("kGlyphWork") = report::kGlyphWork;
  m.attr("kMaxGlyphWork") = report::kMaxGlyphWork;
  m.attr("kMaxDepth") = kMaxDepth;
  m.attr("kMaxDegree") = kMaxDegree;
  m.attr("kMaxImageSize") = kMaxImageSize;
}
