// The settings tables (core/common/settings.hpp) and the envelope plug-in point
// (core/interface/envelope.hpp), issue 24.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/interface/envelope.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/slide/slider.hpp"

using namespace asperity;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Settings, ValidateNamesTheKeyValueAndAllowedSet) {
  slide::SlideOptions o;
  o.minimizer.force_tolerance = 2.0;
  EXPECT_EQ(message_of([&] { o.validate(); }), "solver.tolerance = 2: allowed: (0, 1) G d^2");
  o = {};
  o.max_step = 0.1;
  o.min_step = 0.2;  // each in its range, the pair not
  EXPECT_EQ(message_of([&] { o.validate(); }),
            "slide.min_step = 0.2: allowed: <= slide.max_step = 0.1");
  o = {};
  o.minimizer.max_displacement = std::nan("");
  EXPECT_NE(message_of([&] { o.validate(); }).find("solver.max_displacement = nan"),
            std::string::npos);
  interface::ContactScene c;
  c.a = 600.0;  // in [1, 4096], but not below R = 535
  EXPECT_EQ(message_of([&] { c.validate(); }), "contact.a = 600: allowed: < contact.R = 535");
  EXPECT_NO_THROW(slide::SlideOptions{}.validate());
}

TEST(Settings, TablesComposeWithPrefixesAndSetThroughTheirRows) {
  const auto& t = slide::SlideOptions::settings();
  const auto* tol = settings::find(t, "solver.tolerance");
  const auto* threads = settings::find(t, "fft.threads");
  ASSERT_NE(tol, nullptr);
  ASSERT_NE(threads, nullptr);
  EXPECT_EQ(tol->flag, "--tolerance");
  EXPECT_FALSE(threads->affects_results);
  slide::SlideOptions o;
  tol->set(o, settings::Value(3e-6));
  EXPECT_EQ(o.minimizer.force_tolerance, 3e-6);
  EXPECT_EQ(std::get<double>(tol->get(o)), 3e-6);
  // Keys are unique: one description per setting.
  for (std::size_t i = 0; i < t.size(); ++i)
    for (std::size_t j = i + 1; j < t.size(); ++j)
      EXPECT_NE(t[i].key, t[j].key);
  // Fingerprints: exact values, and without the rows that do not change results.
  const std::string all = settings::fingerprint(o, t);
  const std::string results = settings::fingerprint(o, t, true);
  EXPECT_NE(all.find("solver.tolerance=3e-06"), std::string::npos);
  EXPECT_NE(all.find("fft.threads=1"), std::string::npos);
  EXPECT_EQ(results.find("fft.threads"), std::string::npos);
  o.fft.threads = 2;
  EXPECT_EQ(settings::fingerprint(o, t, true), results);
  EXPECT_NE(settings::fingerprint(o, t), all);
}

// A tool narrows a row it lifted (gf_validate: solver tolerances below 0.01): the lifted row
// refuses what the core row allows, gives the narrower range and its reason, and the core
// table is left as it was.
TEST(Settings, NarrowTightensALiftedRowOnly) {
  struct Tool {
    minimize::MinimizerOptions solver;
  };
  settings::Table<Tool> t;
  settings::lift(
      t, minimize::MinimizerOptions::settings(), "solver.",
      [](auto& s) -> auto& { return s.solver; });
  settings::narrow(t, "solver.tolerance", settings::Range::open(0.0, 1e-2), "converged");
  const auto& row = *settings::find(t, "solver.tolerance");
  EXPECT_EQ(message_of([&] { row.check(settings::Value(0.5)); }),
            "solver.tolerance = 0.5: allowed: (0, 0.01) G d^2");
  EXPECT_NO_THROW(row.check(settings::Value(1e-3)));
  EXPECT_NE(row.meaning.find("(converged)"), std::string::npos);
  const auto& core = *settings::find(minimize::MinimizerOptions::settings(), "tolerance");
  EXPECT_NO_THROW(core.check(settings::Value(0.5)));
  EXPECT_EQ(core.meaning.find("(converged)"), std::string::npos);
  EXPECT_THROW(settings::narrow(t, "solver.no_such_key", settings::Range::any(), ""),
               std::logic_error);
}

TEST(Settings, CheckRefusesWrongKindsAndOutOfRangeValues) {
  const auto& t = minimize::MinimizerOptions::settings();
  const auto& memory = *settings::find(t, "memory");
  EXPECT_NO_THROW(memory.check(settings::Value(8LL)));
  EXPECT_THROW(memory.check(settings::Value(0LL)), std::invalid_argument);
  EXPECT_THROW(memory.check(settings::Value(8.0)), std::invalid_argument);  // not an integer
  EXPECT_THROW(memory.check(settings::Value(1LL << 40)), std::invalid_argument);
  const auto& method = *settings::find(t, "method");
  EXPECT_NO_THROW(method.check(settings::Value(std::string("flow"))));
  EXPECT_EQ(message_of([&] { method.check(settings::Value(std::string("bfgs"))); }),
            "method = \"bfgs\": allowed: one of \"lbfgs\", \"cg\", \"fire\", \"newton\", \"flow\"");
  EXPECT_EQ(settings::Range::closed(0, 1000000).describe(true), "[0, 1000000]");
  EXPECT_FALSE(settings::Range::any().contains(std::nan("")));
}

// A list of numbers (Kind::numbers: a sweep's radii, a scan's core widths): each value checked
// against the row's range, written as [x, y] in fingerprints and summaries.
TEST(Settings, NumberListsCheckEachValueAndPrintAsLists) {
  struct Holder {
    std::vector<double> radii;
  };
  const auto row = settings::numbers<Holder>(
      "sweep.R", [](auto& h) -> auto& { return h.radii; }, settings::Range::positive(), "d",
      "sphere radii");
  Holder h{{535.0, 0.1}};
  EXPECT_NO_THROW(row.check(row.get(h)));
  EXPECT_EQ(settings::to_string(row.get(h)), "[535, 0.1]");
  EXPECT_EQ(message_of([&] {
              row.check(settings::Value(std::vector<double>{535.0, -1.0}));
            }),
            "sweep.R = [535, -1]: allowed: a list of numbers > 0 d");
  EXPECT_THROW(row.check(settings::Value(std::vector<double>{std::nan("")})),
               std::invalid_argument);
  EXPECT_THROW(row.check(settings::Value(2.0)), std::invalid_argument);  // not a list
  row.set(h, settings::Value(std::vector<double>{40.0}));
  EXPECT_EQ(h.radii, std::vector<double>{40.0});
  EXPECT_EQ(settings::fingerprint(h, settings::Table<Holder>{row}), "sweep.R=[40]");
}

// Choices named by integers (a sign): "+1" and "01" name the choice "1"; other names and
// texts stay as they are, for check() to refuse.
TEST(Settings, IntegerChoicesAreNamedByTheirValue) {
  struct Holder {
    int sign = -1;
  };
  const auto row = settings::choice<Holder>(
      "lines.slip_sign", [](auto& h) -> auto& { return h.sign; }, {"-1", "1"},
      [](int s) { return std::to_string(s); },
      [](const std::string& n) { return n == "1" ? 1 : -1; }, "sign");
  EXPECT_EQ(row.choice_named("1"), "1");
  EXPECT_EQ(row.choice_named("+1"), "1");
  EXPECT_EQ(row.choice_named("01"), "1");
  EXPECT_EQ(row.choice_named("-1"), "-1");
  EXPECT_EQ(row.choice_named("-01"), "-1");
  EXPECT_EQ(row.choice_named("0"), "0");
  EXPECT_EQ(row.choice_named("+-1"), "+-1");
  EXPECT_EQ(row.choice_named("1.0"), "1.0");
  EXPECT_EQ(row.choice_named(""), "");
  EXPECT_THROW(row.check(settings::Value(row.choice_named("0"))), std::invalid_argument);
  // Named choices are left alone: "lbfgs" is not an integer.
  settings::Info names;
  names.kind = settings::Kind::choice;
  names.choices = {"lbfgs", "flow"};
  EXPECT_EQ(names.choice_named("+1"), "+1");
  EXPECT_EQ(names.choice_named("flow"), "flow");
  // The integer a sign's name writes (what summary.json echoes); none for named choices, nor
  // for a choice of mixed names.
  EXPECT_EQ(row.integer_choice("-1"), -1);
  EXPECT_EQ(row.integer_choice("1"), 1);
  EXPECT_EQ(names.integer_choice("flow"), std::nullopt);
  names.choices = {"1", "auto"};
  EXPECT_EQ(names.integer_choice("1"), std::nullopt);
}

// A number that may be left out (std::optional<double>): NaN in the row when not given, allowed
// then and only then; a given value is checked as any number's.
TEST(Settings, OptionalNumbersAreNaNWhenNotGiven) {
  struct Holder {
    std::optional<double> k1;
  };
  const auto row = settings::optional_number<Holder>(
      "k1", [](auto& h) -> auto& { return h.k1; }, settings::Range::positive(), "", "prefactor");
  Holder h;
  EXPECT_TRUE(row.optional);
  EXPECT_TRUE(std::isnan(std::get<double>(row.get(h))));
  EXPECT_NO_THROW(row.check(row.get(h)));
  EXPECT_EQ(row.allowed(), "> 0, or not given");
  row.set(h, settings::Value(2.5));
  ASSERT_TRUE(h.k1.has_value());
  EXPECT_EQ(*h.k1, 2.5);
  EXPECT_EQ(std::get<double>(row.get(h)), 2.5);
  EXPECT_EQ(message_of([&] { row.check(settings::Value(-1.0)); }),
            "k1 = -1: allowed: > 0, or not given");
  EXPECT_THROW(row.check(settings::Value(INFINITY)), std::invalid_argument);
  row.set(h, settings::Value(std::nan("")));
  EXPECT_FALSE(h.k1.has_value());
  // A plain number still refuses NaN.
  const auto plain = settings::number<Holder>(
      "x", [](auto& o) -> auto& { return *o.k1; }, settings::Range::any(), "", "x");
  EXPECT_FALSE(plain.optional);
  EXPECT_THROW(plain.check(settings::Value(std::nan(""))), std::invalid_argument);
}

// The Hertz envelope: tau_max = alpha p(r) with the Hertz p (MODEL.md 3), zero outside a.
TEST(Envelope, HertzIsAlphaTimesTheHertzPressure) {
  interface::ContactScene c;
  const auto e = interface::make_envelope(c);
  const auto h = c.hertz();
  for (double r : {0.0, 10.0, 42.9, 43.0, 50.0}) {
    EXPECT_EQ(e->pressure(r), h.pressure(r));
    EXPECT_EQ(e->tau_max(r), c.alpha * h.pressure(r));
  }
  EXPECT_EQ(e->tau_max(43.5), 0.0);
  c.envelope = "jkr";  // not an envelope of this build
  EXPECT_THROW(interface::make_envelope(c), std::invalid_argument);
  EXPECT_THROW(c.validate(), std::invalid_argument);
  EXPECT_EQ(interface::envelope_names(), (std::vector<std::string>{"hertz", "adhesive", "mixed"}));
}

}  // namespace
