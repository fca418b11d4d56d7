// One table of keys per options struct: loading keeps the field's current value when a key is
// absent, checks values with IniSection's messages, and the dump, the saved ini and keys() list
// the same keys in the same order.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/OptionTable.h"

using namespace budget_slam;

namespace {

enum class Colour { Red, Green };

struct ToyOptions : public TabledOptions<ToyOptions> {
  static constexpr const char* kSection = "Toy";
  std::size_t count = 3;
  double ratio = 0.5;
  bool on = false;
  std::string name = "x";
  Colour colour = Colour::Red;
  std::vector<std::string> items;

  static const OptionTable<ToyOptions>& table() {
    static const EnumNames<Colour> colours = {{"red", Colour::Red}, {"green", Colour::Green}};
    static const OptionTable<ToyOptions> t = {
        option::integer("count", &ToyOptions::count, 1, 10, "[things]"),
        option::real("ratio", &ToyOptions::ratio, 0.0, 1.0),
        option::flag("on", &ToyOptions::on),
        option::text("name", &ToyOptions::name),
        option::choice("colour", &ToyOptions::colour, colours),
        option::list("items", &ToyOptions::items),
    };
    return t;
  }
};

std::string errorOf(const mrpt::config::CConfigFileMemory& ini) {
  try {
    ToyOptions().loadFromConfigFile(ini, ToyOptions::kSection);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string dumpOf(const ToyOptions& o) {
  std::ostringstream out;
  o.dumpToTextStream(out);
  return out.str();
}

}  // namespace

TEST(OptionTable, AbsentKeysKeepTheCurrentValue) {
  mrpt::config::CConfigFileMemory ini;
  ToyOptions o;
  o.count = 7;
  o.colour = Colour::Green;
  o.items = {"a"};
  o.loadFromConfigFile(ini, ToyOptions::kSection);
  EXPECT_EQ(o.count, 7u);
  EXPECT_EQ(o.colour, Colour::Green);
  EXPECT_EQ(o.items, std::vector<std::string>{"a"});
}

TEST(OptionTable, ReadsAndChecksEveryKind) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("Toy", "count", "4  // comment");
  ini.write("Toy", "ratio", "0.25");
  ini.write("Toy", "on", "yes");
  ini.write("Toy", "name", "y");
  ini.write("Toy", "colour", "green");
  ini.write("Toy", "items", "a, b c");
  ToyOptions o;
  o.loadFromConfigFile(ini, "Toy");
  EXPECT_EQ(o.count, 4u);
  EXPECT_DOUBLE_EQ(o.ratio, 0.25);
  EXPECT_TRUE(o.on);
  EXPECT_EQ(o.name, "y");
  EXPECT_EQ(o.colour, Colour::Green);
  EXPECT_EQ(o.items, (std::vector<std::string>{"a", "b", "c"}));

  ini.write("Toy", "count", "11");
  EXPECT_EQ(errorOf(ini), "[Toy] count = 11: must be at most 10");
  ini.write("Toy", "count", "1");
  ini.write("Toy", "colour", "blue");
  EXPECT_EQ(errorOf(ini), "[Toy] colour = 'blue': must be one of red, green");
}

TEST(OptionTable, DumpSaveAndKeysListTheSameKeys) {
  ToyOptions o;
  o.items = {"a", "b"};
  EXPECT_EQ(ToyOptions::keys(),
            (std::vector<std::string>{"count", "ratio", "on", "name", "colour", "items"}));
  EXPECT_EQ(dumpOf(o),
            "\n----------- [Toy] ------------\n"
            "count                    = 3  // [things]\n"
            "ratio                    = 0.5\n"
            "on                       = false\n"
            "name                     = x\n"
            "colour                   = red\n"
            "items                    = a,b\n");

  // What save writes loads back to the same values.
  mrpt::config::CConfigFileMemory ini;
  o.count = 9;
  o.ratio = 0.1234567891;  // more digits than a default stream shows
  o.colour = Colour::Green;
  o.saveToConfigFile(ini, "Toy");
  ToyOptions back;
  back.loadFromConfigFile(ini, "Toy");
  EXPECT_EQ(back.ratio, o.ratio);
  EXPECT_EQ(dumpOf(back), dumpOf(o));
}
