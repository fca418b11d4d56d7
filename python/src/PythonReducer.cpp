// Reducers written in Python (docs/PYTHON.md "A reducer in Python"). A plugin is a Python class
// registered by name (budget_slam.register_reducer); its registry entry is an ordinary
// ReducerEntry: its ini section is checked in C++ before a run (no Python needed), and each run
// builds an instance and asks its choose() at every drop, the GIL taken back for the call (the
// runs release it: RunGuard.h runGuarded, PluginHost.cpp). What the plugin does wrong (raises,
// returns what is not a candidate, a NaN score) ends the run `failed` with one line naming the
// plugin, the step and the Python error's last line; a stop request (Ctrl-C) interrupts Python
// code that does not return (StopWatch).
#include "PythonReducer.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <iomanip>
#include <variant>

#include "PluginViews.h"
#include "StopWatch.h"

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/engine/MappingOptions.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BudgetOptions.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/ReportOptions.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace py = pybind11;

namespace budget_slam::python {
namespace {

/// One key of a plugin's ini section: its kind (from the Python default's type), its default as
/// ini text, and for a choice the allowed words, for a number its range.
struct PluginOption {
  enum class Kind { Bool, Int, Float, Text, Choice };
  std::string key;
  Kind kind = Kind::Text;
  std::string default_text;
  std::vector<std::string> choices;  ///< Kind::Choice: the allowed words, the default first
  double lo = -std::numeric_limits<double>::infinity();  ///< Int, Float: the smallest value
  double hi = std::numeric_limits<double>::infinity();   ///< Int, Float: the largest value
  std::string doc;
};

using OptionValue = std::variant<bool, long long, double, std::string>;

/// What register_reducer was given, shared by the registry entry and every instance.
struct PluginSpec {
  std::string name;     ///< the registry name
  std::string origin;   ///< where the class is defined (its file), for messages
  std::string section;  ///< its ini section
  std::string summary;
  std::vector<PluginOption> options;
  /// The class (or factory) called with the section's values as keyword arguments. A strong
  /// reference never released: the registry is a static that outlives the interpreter, and a
  /// reducer's name stays taken for the life of the process.
  PyObject* factory = nullptr;

  /// "plugin reducer 'mine' (mine.py)": how every error of the plugin begins.
  std::string label() const { return "plugin reducer '" + name + "' (" + origin + ")"; }
};

long long toLongLong(double v) {
  return v <= -9.2e18  ? std::numeric_limits<long long>::min()
         : v >= 9.2e18 ? std::numeric_limits<long long>::max()
                       : static_cast<long long>(v);
}

/// Reads every key of the plugin's section as the plugin will get it; the first bad value throws
/// IniSection's KeyError ("[S] k = v: why"). Needs no GIL: it runs in the checks before a run.
std::vector<OptionValue> readValues(const PluginSpec& spec,
                                    const mrpt::config::CConfigFileBase& ini) {
  const IniSection s(ini, spec.section);
  std::vector<OptionValue> out;
  for (const auto& o : spec.options) switch (o.kind) {
      case PluginOption::Kind::Bool:
        out.emplace_back(s.readBool(o.key, o.default_text == "true"));
        break;
      case PluginOption::Kind::Int:
        out.emplace_back(
            s.readInt(o.key, std::stoll(o.default_text), toLongLong(o.lo), toLongLong(o.hi)));
        break;
      case PluginOption::Kind::Float:
        out.emplace_back(s.readDouble(o.key, std::stod(o.default_text), o.lo, o.hi));
        break;
      case PluginOption::Kind::Text:
        out.emplace_back(s.readString(o.key, o.default_text));
        break;
      case PluginOption::Kind::Choice:
        out.emplace_back(s.readChoice(o.key, o.default_text, o.choices));
        break;
    }
  return out;
}

std::string valueText(const OptionValue& v) {
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (const long long* i = std::get_if<long long>(&v)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&v)) return option::numberText(*d);
  return std::get<std::string>(v);
}

py::object toPython(const OptionValue& v) {
  if (const bool* b = std::get_if<bool>(&v)) return py::bool_(*b);
  if (const long long* i = std::get_if<long long>(&v)) return py::int_(*i);
  if (const double* d = std::get_if<double>(&v)) return py::float_(*d);
  return py::str(std::get<std::string>(v));
}

/// The last line of a Python error as traceback prints it ("ValueError: boom"), on one line.
std::string pythonErrorLine(const py::error_already_set& e) {
  try {
    const py::list lines =
        py::module_::import("traceback").attr("format_exception_only")(e.type(), e.value());
    std::string last =
        lines.empty() ? std::string() : py::str(lines[lines.size() - 1]).cast<std::string>();
    for (char& c : last)
      if (c == '\n' || c == '\r') c = ' ';
    while (!last.empty() && last.back() == ' ') last.pop_back();
    return last.empty() ? std::string("an exception without a message") : last;
  } catch (...) {
    return "an exception that cannot be printed";
  }
}

/// What a plugin returned or did that its contract does not allow (a wrong type, an id that is
/// not a candidate, a NaN score): worded without the plugin's name and step, which the caller adds.
class PluginFault : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* typeName(py::handle h) { return Py_TYPE(h.ptr())->tp_name; }

/// A Python reducer in a run: the instance register_reducer's class built, asked at each drop.
class PythonReducer : public Reducer {
 public:
  /// Built with the GIL held.
  PythonReducer(std::shared_ptr<const PluginSpec> spec, py::object instance,
                std::vector<OptionValue> values, std::uint64_t seed)
      : spec_(std::move(spec)),
        values_(std::move(values)),
        seed_(seed),
        instance_(std::move(instance)),
        choose_(instance_.attr("choose")) {}

  ~PythonReducer() override {
    // The watch's thread may wait for the GIL: join it without holding it.
    if (Py_IsInitialized() && PyGILState_Check()) {
      py::gil_scoped_release release;
      watch_.reset();
    } else {
      watch_.reset();
    }
    if (!Py_IsInitialized()) {  // the interpreter is gone: the references are left as they are
      instance_.release(), choose_.release(), observe_.release(), forget_.release();
      return;
    }
    py::gil_scoped_acquire gil;
    instance_ = py::object(), choose_ = py::object(), observe_ = py::object(),
    forget_ = py::object();
  }

  std::string name() const override { return spec_->name; }

  ReducerChoice choose(const DropContext& ctx) override {
    last_step_ = ctx.step;
    return callPython(ctx.step, [&] {
      // Owned by Python: a plugin that keeps its Drop keeps an expired one, never a dangling one.
      py::object drop = py::cast(DropView(ctx, seed_));
      DropView& view = drop.cast<DropView&>();
      struct Expire {
        DropView& v;
        ~Expire() { v.expire(); }
      } expire{view};
      const py::object result = choose_(drop);
      return interpret(result, ctx);
    });
  }

  void dumpOptions(std::ostream& out) const override {
    if (spec_->options.empty()) return;
    out << "\n----------- [" << spec_->section << "] ------------\n";
    for (std::size_t i = 0; i < spec_->options.size(); ++i) {
      out << std::left << std::setw(25) << spec_->options[i].key << "= " << valueText(values_[i]);
      if (!spec_->options[i].doc.empty()) out << "  // " << spec_->options[i].doc;
      out << "\n";
    }
  }

 protected:
  /// Runs `f` (Python code) with the GIL, under the stop watch. A Python exception or a
  /// PluginFault becomes the run's one-line Error naming the plugin and the step; an exception
  /// after a stop request is the stop (Interrupted).
  template <class F>
  auto callPython(StepIndex step, F&& f) -> decltype(f()) {
    Cancellation::check();
    py::gil_scoped_acquire gil;
    if (!watch_) watch_ = std::make_unique<StopWatch>();
    watch_->enter();
    struct Leave {
      StopWatch& w;
      ~Leave() { w.leave(); }
    } leave{*watch_};
    try {
      return f();
    } catch (const py::error_already_set& e) {
      Cancellation::check();
      throw Error(failure(step, pythonErrorLine(e)));
    } catch (const PluginFault& e) {
      throw Error(failure(step, e.what()));
    } catch (const std::runtime_error& e) {  // a C++ exception of a Drop's method, if uncaught
      Cancellation::check();
      throw Error(failure(step, e.what()));
    }
  }

  std::string failure(StepIndex step, const std::string& what) const {
    return spec_->label() + ": step " + std::to_string(step) + ": " + what;
  }

  /// The plugin's answer as a choice: a landmark id (score 0), (id, score), or one score per
  /// candidate in `candidates` order (the lowest goes; ties to the lowest id, as the shipped
  /// reducers break them).
  ReducerChoice interpret(const py::object& r, const DropContext& ctx) const {
    const auto isCandidate = [&](LandmarkId id) {
      for (const std::size_t i : ctx.candidates)
        if (ctx.landmarks[i].id == id) return true;
      return false;
    };
    const auto idOf = [&](py::handle h) -> LandmarkId {
      if (py::isinstance<py::bool_>(h) || !PyIndex_Check(h.ptr()))
        throw PluginFault(std::string("choose returned ") + typeName(r.ptr()) +
                          ", expected a landmark id, (id, score) or one score per candidate");
      const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(h.ptr()));
      long long id = index ? PyLong_AsLongLong(index.ptr()) : -1;
      if (!index || (id == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        throw PluginFault(std::string("choose returned ") + typeName(h) +
                          " that is not a landmark id");
      }
      if (!isCandidate(static_cast<LandmarkId>(id)))
        throw PluginFault("choose returned landmark " + std::to_string(id) +
                          ", not a candidate of this drop");
      return static_cast<LandmarkId>(id);
    };
    const auto finite = [](double s, LandmarkId id) {
      if (!std::isfinite(s))
        throw PluginFault("choose gave landmark " + std::to_string(id) + " the score " +
                          formatScore(s) + ", not a finite number");
      return s;
    };
    const bool array = py::isinstance<py::array>(r);
    if (array ? py::array(r).ndim() == 0 : PyIndex_Check(r.ptr()) && !py::isinstance<py::bool_>(r))
      return {idOf(r), 0.0};
    if (py::isinstance<py::tuple>(r) && py::len(r) == 2) {
      const py::tuple t = r;
      const LandmarkId id = idOf(t[0]);
      const double s = PyFloat_AsDouble(t[1].ptr());
      if (s == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        throw PluginFault(std::string("choose returned (id, ") + typeName(t[1]) +
                          "), expected (id, score) with a number as score");
      }
      return {id, finite(s, id)};
    }
    if (!py::isinstance<py::str>(r) && !py::isinstance<py::bytes>(r) &&
        (array || py::isinstance<py::list>(r) || py::isinstance<py::tuple>(r))) {
      const auto scores = py::array_t<double, py::array::forcecast>::ensure(r);
      if (!scores || scores.ndim() != 1)
        throw PluginFault(std::string("choose returned a ") + typeName(r.ptr()) +
                          " that is not one number per candidate");
      if (static_cast<std::size_t>(scores.shape(0)) != ctx.candidates.size())
        throw PluginFault("choose returned " + std::to_string(scores.shape(0)) + " scores for " +
                          std::to_string(ctx.candidates.size()) + " candidates");
      ReducerChoice best;
      const auto v = scores.unchecked<1>();
      for (std::size_t k = 0; k < ctx.candidates.size(); ++k) {
        const LandmarkId id = ctx.landmarks[ctx.candidates[k]].id;
        const double s = finite(v(static_cast<py::ssize_t>(k)), id);
        if (k == 0 || s < best.score || (s == best.score && id < best.id)) best = {id, s};
      }
      return best;
    }
    throw PluginFault(std::string("choose returned ") + typeName(r.ptr()) +
                      ", expected a landmark id, (id, score) or one score per candidate");
  }

  static std::string formatScore(double s) {
    return std::isnan(s) ? "nan" : (s > 0 ? "inf" : "-inf");
  }

  std::shared_ptr<const PluginSpec> spec_;
  std::vector<OptionValue> values_;
  std::uint64_t seed_;
  StepIndex last_step_ = 0;  ///< the step of the last call, for forget()'s messages
  py::object instance_, choose_, observe_, forget_;
  std::unique_ptr<StopWatch> watch_;
};

/// A Python reducer whose class has observe(seen) (and maybe forget(id)): told every step's
/// observations, as place-coverage is (core/Reducer.h ObservationKeeper).
class PythonObservingReducer : public PythonReducer, public ObservationKeeper {
 public:
  PythonObservingReducer(std::shared_ptr<const PluginSpec> spec, py::object instance,
                         std::vector<OptionValue> values, std::uint64_t seed)
      : PythonReducer(std::move(spec), std::move(instance), std::move(values), seed) {
    observe_ = instance_.attr("observe");
    if (py::hasattr(instance_, "forget")) forget_ = instance_.attr("forget");
  }

  void observe(const StepObservation& seen) override {
    last_step_ = seen.step;
    callPython(seen.step, [&] { observe_(SeenView{seen}); });
  }
  void forget(LandmarkId id) override {
    if (!forget_) return;
    callPython(last_step_, [&] { forget_(static_cast<long long>(id)); });
  }
};

/// The sections a plugin may not take: the application's own, the backends' and the reducers'.
void checkSectionIsFree(const std::string& section) {
  std::vector<std::string> taken = {
      runs::MappingOptions::kSection,    reducers::BudgetOptions::kSection,
      metrics::MetricsOptions::kSection, runs::LocalizationOptions::kSection,
      report::ReportOptions::kSection,   wakeup::WakeUpOptions::kSection};
  for (const auto* e : runs::builtinBackends().entries())
    for (const auto& s : e->sections) taken.push_back(s.name);
  for (const auto* e : reducers::builtinReducers().entries())
    for (const auto& s : e->sections) taken.push_back(s.name);
  for (const auto& t : taken)
    if (lowerAscii(t) == lowerAscii(section))
      throw ConfigError("register_reducer: section [" + section +
                        "] is taken: give the plugin a section of its own (section=...)");
}

/// register_reducer's C++ half (python/budget_slam/__init__.py checks the Python side and turns
/// the options dict into `options`: tuples (key, kind, default text, choices, lo, hi, doc)).
void registerReducer(const std::string& name, py::object factory, const std::string& section,
                     const std::string& summary, const std::string& origin,
                     const std::vector<py::tuple>& options) {
  const auto& registry = reducers::builtinReducers();
  if (name.empty() || name.find_first_of(" \t\r\n,;:=[]/\\\"'") != std::string::npos)
    throw ConfigError("register_reducer: name '" + printable(name) +
                      "': use letters, digits, '-' and '_' (it is a word of the ini and of "
                      "--reducers a,b,c)");
  if (registry.has(name))
    throw ConfigError("register_reducer: reducer '" + name +
                      "' is already registered (a name stays taken for the life of the process)");
  if (section.empty() || section.find_first_of("[]\r\n=") != std::string::npos)
    throw ConfigError("register_reducer: section '" + printable(section) +
                      "' is not a section name");
  if (!options.empty()) checkSectionIsFree(section);
  if (!PyCallable_Check(factory.ptr()))
    throw ConfigError("register_reducer: '" + name + "': expected a class, got " +
                      typeName(factory.ptr()));

  auto spec = std::make_shared<PluginSpec>();
  spec->name = name, spec->section = section, spec->summary = summary, spec->origin = origin;
  for (const py::tuple& t : options) {
    PluginOption o;
    o.key = t[0].cast<std::string>();
    const auto kind = t[1].cast<std::string>();
    o.kind = kind == "bool"     ? PluginOption::Kind::Bool
             : kind == "int"    ? PluginOption::Kind::Int
             : kind == "float"  ? PluginOption::Kind::Float
             : kind == "choice" ? PluginOption::Kind::Choice
                                : PluginOption::Kind::Text;
    o.default_text = t[2].cast<std::string>();
    o.choices = t[3].cast<std::vector<std::string>>();
    o.lo = t[4].cast<double>(), o.hi = t[5].cast<double>();
    o.doc = t[6].cast<std::string>();
    spec->options.push_back(std::move(o));
  }
  // The defaults, written out, must pass the section's own checks (a number within its range).
  try {
    std::string text = "[" + section + "]\n";
    for (const auto& o : spec->options) text += o.key + " = " + o.default_text + "\n";
    readValues(*spec, mrpt::config::CConfigFileMemory(text));
  } catch (const ConfigError& e) {
    throw ConfigError("register_reducer: '" + name +
                      "': a default fails its own check: " + e.what());
  }
  spec->factory = factory.inc_ref().ptr();  // never released (PluginSpec::factory)

  OptionSection s;
  s.name = section;
  for (const auto& o : spec->options) {
    std::string doc = o.doc;
    if (o.kind == PluginOption::Kind::Choice) {
      std::string words;
      for (const auto& c : o.choices) words += (words.empty() ? "" : ", ") + c;
      doc = (doc.empty() ? "" : doc + "; ") + "one of " + words;
    }
    s.options.push_back({o.key, o.default_text, doc});
  }
  std::shared_ptr<const PluginSpec> shared = spec;
  s.check = [shared](const mrpt::config::CConfigFileBase& ini) { readValues(*shared, ini); };

  ReducerEntry entry;
  entry.name = name;
  entry.summary = summary;
  if (!spec->options.empty()) entry.sections.push_back(std::move(s));
  entry.factory = [shared](const mrpt::config::CConfigFileBase& ini,
                           std::uint64_t seed) -> std::unique_ptr<Reducer> {
    std::vector<OptionValue> values = readValues(*shared, ini);
    py::gil_scoped_acquire gil;
    py::dict kwargs;
    for (std::size_t i = 0; i < values.size(); ++i)
      kwargs[py::str(shared->options[i].key)] = toPython(values[i]);
    py::object instance;
    try {
      instance = py::reinterpret_borrow<py::object>(shared->factory)(**kwargs);
    } catch (const py::error_already_set& e) {
      throw Error(shared->label() + ": building it: " + pythonErrorLine(e));
    }
    if (!py::hasattr(instance, "choose") || !PyCallable_Check(instance.attr("choose").ptr()))
      throw Error(shared->label() + ": a " + typeName(instance.ptr()) +
                  " has no choose(drop) method");
    if (py::hasattr(instance, "observe"))
      return std::make_unique<PythonObservingReducer>(shared, std::move(instance),
                                                      std::move(values), seed);
    return std::make_unique<PythonReducer>(shared, std::move(instance), std::move(values), seed);
  };
  reducers::addReducer(std::move(entry));
}

}  // namespace

void definePluginApi(py::module_& m) {
  definePluginViews(m);
  m.def("register_reducer", &registerReducer, py::arg("name"), py::arg("factory"),
        py::arg("section"), py::arg("summary"), py::arg("origin"), py::arg("options"),
        "The C++ half of budget_slam.register_reducer (which checks and converts the options).");
}

}  // namespace budget_slam::python
