// A reducer added to budget-slam by this one file: its class, its options, its registry entry and
// the one line that registers it (at the end). test_added_reducer.cpp uses it end to end.
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/reducers/BuiltinReducers.h"

namespace budget_slam::testing {
namespace {

/// [IdOrderReducer]: which end of the id range goes first.
struct IdOrderOptions : public TabledOptions<IdOrderOptions> {
  static constexpr const char* kSection = "IdOrderReducer";
  enum class Order { Lowest, Highest };
  Order order = Order::Lowest;  ///< lowest: the candidate of lowest id goes; highest: the highest

  static const OptionTable<IdOrderOptions>& table() {
    static const EnumNames<Order> names = {{"lowest", Order::Lowest}, {"highest", Order::Highest}};
    static const OptionTable<IdOrderOptions> t = {
        option::choice("order", &IdOrderOptions::order, names, "lowest or highest id first")};
    return t;
  }
};

/// `id-order`: drops the candidate of lowest (or highest) landmark id; score: that id.
class IdOrderReducer : public Reducer {
 public:
  static constexpr const char* kName = "id-order";
  explicit IdOrderReducer(const IdOrderOptions& o) : options_(o) {}
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override {
    const bool lowest = options_.order == IdOrderOptions::Order::Lowest;
    LandmarkId best = ctx.landmarks[ctx.candidates.front()].id;
    for (const std::size_t i : ctx.candidates) {
      const LandmarkId id = ctx.landmarks[i].id;
      if (lowest ? id < best : id > best) best = id;
    }
    return {best, static_cast<double>(best)};
  }
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }

  static ReducerEntry entry() {
    return {kName,
            "the candidate of lowest (or highest) landmark id (a test's reducer)",
            {tabledSection<IdOrderOptions>()},
            [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
              IdOrderOptions o;
              o.loadFromConfigFile(ini, IdOrderOptions::kSection);
              return std::make_unique<IdOrderReducer>(o);
            }};
  }

 private:
  IdOrderOptions options_;
};

}  // namespace

// The one registration line.
static const bool kAdded = reducers::addReducer(IdOrderReducer::entry());

}  // namespace budget_slam::testing
