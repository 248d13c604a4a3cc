// fit_scaling: the scaling laws of MODEL.md section 8 fitted to friction_sweep tables and compared
// with the Peierls-cell prediction of Regime III (issue 9). Reads one or more sweep.csv files and a
// peierls_scan summary (or k1, k2 given), and writes into the output directory
// - summary.json: c0 with its error and window, k1, k2 and f_P used, the Regime I and the II -> III
//   crossovers, the Regime III comparison per R, the regime-map agreement, a Regime III fit of
//   k1, k2 to the friction data where they rise; times and provenance under "run";
// - predictions.csv: per data point, mu/alpha measured and every prediction, both regimes;
// - forecast.csv (--forecast-R, --forecast-a): the prediction at contacts without data, with its
//   error and its slope in a, and the II -> III crossover at those R in summary.json;
// - collapse.png: mu/alpha vs a/b_core^0 (log-log), data by model and R, the Regime I line, the
//   fitted Regime II law and the nucleation condition, the Regime III predictions per R;
// - regime_map.png: predicted mu/alpha over (a/d, R/d) with the regime boundaries and the data
//   points marked by their simulated regime.
// Tables of the adhesive and mixed envelopes (issue 27; fit_io.hpp) are fitted with their own law
// (adhesive_predictions.csv, adhesive_collapse.png) or set against both limits
// (mixed_predictions.csv, mixed_limits.png); the Peierls law is needed for Hertz tables only.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "fit_io.hpp"

using namespace asperity;
using namespace asperity::app::fit_scaling;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Fit c0, compare with the Peierls prediction of Regime III, map the regimes"};
    Options o;
    cli.add_option("sweeps", o.sweeps,
                   "friction_sweep tables (sweep.csv) or output folders (required, but for "
                   "--list-settings)");
    cli.add_option("--peierls", o.peierls,
                   "peierls_scan summary.json (or its folder): k1, k2 of the edge fit");
    app::SettingFlags flags;
    const Options defaults;
    flags.add(cli, Options::settings(), {}, "summary key", &defaults);
    cli.add_option("--out", o.out, "Output directory")->capture_default_str();
    app::add_list_settings(cli, Options::settings(), Options{}, "docs/nucleation.md");
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    flags.apply(Options::settings(), o);
    o.validate();

    const auto t0 = std::chrono::steady_clock::now();
    const Loaded data = load_sweeps(o.sweeps);
    const ByEnvelope by = split_envelopes(data.points);
    if (!o.forecast_R.empty() && by.hertz.empty())
      throw std::invalid_argument(
          "--forecast-R, --forecast-a: the forecast is of the Hertz law, and no table is Hertz");
    if (!by.hertz.empty() && !o.has_law())
      throw std::invalid_argument(
          "--peierls or both --k1 and --k2 are required (Regime III law of the Hertz tables)");
    std::optional<LawSource> law;
    if (o.has_law() || o.k1 || o.k2) law = read_law(o);
    std::optional<Analysis> hertz;
    if (!by.hertz.empty()) hertz = analyse(by.hertz, *law, o);
    std::optional<AdhesiveAnalysis> adhesive;
    if (!by.adhesive.empty()) adhesive = analyse_adhesive(by.adhesive, o);
    std::optional<MixedAnalysis> mixed;
    if (!by.mixed.empty()) {
      // Each limit's c0: fitted from the tables of its envelope given along, else given.
      const auto limit = [](const auto& fitted, const std::optional<double>& given,
                            const char* flag) {
        LimitC0 l;
        if (fitted) {
          l = {fitted->fit.c0, fitted->fit.c0_error, "fitted to this run's tables"};
        } else if (given) {
          l = {*given, std::numeric_limits<double>::quiet_NaN(), flag};
        }
        return l;
      };
      mixed = analyse_mixed(by.mixed, limit(hertz, o.c0_hertz, "--c0-hertz"),
                            limit(adhesive, o.c0_adhesive, "--c0-adhesive"));
    }

    const fs::path dir = app::ensure_directory(o.out);
    app::remove_stale_temporaries(dir);
    std::vector<fs::path> figures;
    if (hertz) {
      write_predictions(dir / "predictions.csv", by.hertz, *hertz);
      // A forecast.csv left in the folder by an earlier run is not this run's.
      if (hertz->forecasts.empty()) {
        fs::remove(dir / "forecast.csv");
      } else {
        write_forecast(dir / "forecast.csv", *hertz);
      }
      figures = write_figures(dir, by.hertz, *law, *hertz, o);
    }
    if (adhesive) {
      write_adhesive_predictions(dir / "adhesive_predictions.csv", by.adhesive, *adhesive);
      figures.push_back(write_adhesive_figure(dir, by.adhesive, *adhesive));
    }
    if (mixed) {
      write_mixed_predictions(dir / "mixed_predictions.csv", by.mixed, *mixed);
      figures.push_back(write_mixed_figure(dir, by.mixed, *mixed));
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Results res{.points = &by,
                      .law = law ? &*law : nullptr,
                      .hertz = hertz ? &*hertz : nullptr,
                      .adhesive = adhesive ? &*adhesive : nullptr,
                      .mixed = mixed ? &*mixed : nullptr};
    write_summary(dir / "summary.json", data, res, o, figures, wall);
    print_report(dir, res, o, figures);
    return 0;
  });
}
