// contact_slide: quasi-static sliding of a sphere on a crystalline flat in the lateral force
// model (MODEL.md sections 3 and 5). Reads a scene (default: data/scenes/default.toml), lets
// flags override it, and writes trace.csv, summary.json, figures and NetCDF snapshots.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common/cli.hpp"
#include "common/cli_checks.hpp"
#include "common/slide_io.hpp"

using namespace asperity;

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Quasi-static sliding of a sphere on a crystalline flat (lateral force model)"};
    std::string scene_path = ASPERITY_DATA_DIR "/scenes/default.toml";
    std::string out = "results/contact_slide";
    std::optional<double> a, R, alpha, nu, distance, tolerance;
    std::optional<std::string> protocol, solver;
    std::optional<int> threads;
    cli.add_option("scene", scene_path, "Scene file (TOML)")
        ->check(CLI::ExistingFile)
        ->capture_default_str();
    cli.add_option("--a", a, "Contact radius (d)")->check(app::finite_number(1.0, 4096.0));
    cli.add_option("--R", R, "Sphere radius (d)")->check(app::positive());
    cli.add_option("--alpha", alpha, "Local friction coefficient")
        ->check(app::finite_number(0.0, 10.0, true));
    cli.add_option("--nu", nu, "Poisson ratio")->check(app::finite_number(0.0, 0.5));
    cli.add_option("--distance", distance, "Sliding distance (d); 0: automatic")
        ->check(app::non_negative());
    cli.add_option("--protocol", protocol, "adaptive | reference")
        ->check(CLI::IsMember({"adaptive", "reference"}));
    cli.add_option("--solver", solver, "lbfgs | cg | fire | newton")
        ->check(CLI::IsMember({"lbfgs", "cg", "fire", "newton"}));
    cli.add_option("--tolerance", tolerance, "Force tolerance per site (G d^2)")
        ->check(app::finite_number(0.0, 1.0, true));
    cli.add_option("--threads", threads, "FFT threads")->check(CLI::Range(1, 1024));
    cli.add_option("--out", out, "Output directory")->capture_default_str();
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;

    app::SlideScene s = app::read_slide_scene(scene_path);
    if (a) s.contact.a = *a;
    if (R) s.contact.R = *R;
    if (alpha) s.contact.alpha = *alpha;
    if (nu) s.contact.material.nu = *nu;
    if (distance) s.options.distance = *distance;
    if (protocol) s.options.protocol = slide::protocol_from_string(*protocol);
    if (solver) s.options.minimizer.method = minimize::method_from_string(*solver);
    if (tolerance) s.options.minimizer.force_tolerance = *tolerance;
    if (threads) s.options.fft.threads = *threads;
    s.contact.validate();
    s.options.validate();

    std::fprintf(stderr,
                 "contact_slide: a = %g d, R = %g d, alpha = %g, nu = %g: a/b_core^0 = %.3g, "
                 "lambda = %.3g; %s protocol, %s, tolerance %g\n",
                 s.contact.a, s.contact.R, s.contact.alpha, s.contact.material.nu,
                 s.contact.a_over_bcore0(), s.contact.lambda(),
                 slide::to_string(s.options.protocol).c_str(),
                 minimize::to_string(s.options.minimizer.method).c_str(),
                 s.options.minimizer.force_tolerance);
    const bool tty = isatty(2) != 0;
    // In a log (no terminal) a line at each slip event and otherwise every 10 s: the automatic
    // distance is capped generously, so fractions of the cap say little.
    const auto progress = [tty, last = std::chrono::steady_clock::now(), last_slips = 0](
                              double Dx, double limit, int slips) mutable {
      if (tty) {
        std::fprintf(stderr, "\r  Dx = %7.4f d of at most %.2f d, slip events: %d   ", Dx, limit,
                     slips);
        return;
      }
      const auto now = std::chrono::steady_clock::now();
      if (slips != last_slips || now - last > std::chrono::seconds(10)) {
        std::fprintf(stderr, "  Dx = %.4f d of at most %.2f d, slip events: %d\n", Dx, limit,
                     slips);
        last = now;
        last_slips = slips;
      }
    };
    const slide::SlideResult r = slide::slide(s.contact, s.options, progress);
    if (tty) std::fprintf(stderr, "\n");
    const auto files = app::write_slide_outputs(out, s, r);

    std::printf(
        "mu = %.6f, mu/alpha = %.5f%s (peak at Dx = %.4f d, precision %.1e), "
        "kinetic/static = %.3f, slip events %d\n",
        r.mu, r.mu_over_alpha, r.mu_is_lower_bound ? " (lower bound)" : "", r.peak_Dx,
        r.peak_precision, r.kinetic_over_static, r.slip_events);
    std::printf(
        "stopped: %s at Dx = %.4f d; %d steps, %d minimisations, %zu GF applications, "
        "%.2f s\n",
        r.stop_reason.c_str(), r.distance, r.steps, r.minimizations, r.gf_applications, r.wall_s);
    std::printf("results: %s\n", (std::filesystem::path(out) / "summary.json").c_str());
    std::printf("figures:");
    for (const auto& f : files) {
      if (f.extension() == ".png") std::printf(" %s", f.c_str());
    }
    std::printf("\n");
    return r.failed ? 1 : 0;
  });
}
