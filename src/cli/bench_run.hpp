// The fields of one `hemirad bench-run` measurement, shared by the one-process run and the MPI
// driver's (which computes F and solves across ranks, then records the same fields on rank 0).
#pragma once

#include "cli/bench_records.hpp"
#include "cli/options.hpp"
#include "preprocess/form_factor_job.hpp"
#include "solve/solver.hpp"

#include <string>
#include <vector>

namespace hemirad {

/// The scene as bench-run loads it (no warnings printed; --subdivide applied).
Scene loadBenchScene(const Options& o);
/// This process's peak resident memory in MiB (VmHWM).
double peakRssMiB();

/// The scene, its size, the back end and its description of the run.
void recordScene(BenchRecord& r, const Options& o, const Scene& scene, double loadSeconds);
/// The computed F: post-processing, times, rows, rays, nonzeros, statistics, per-row stage times.
void recordFormFactors(BenchRecord& r, const Options& o, const FormFactorRun& run);
/// The solve (time, solver, most iterations over the channels) and t_total.
void recordSolve(BenchRecord& r, const Radiosity& B, const std::string& solver, double seconds, const FormFactorRun& run);
/// Errors of F against --reference and of B against --reference-radiosity, when given.
void recordErrors(BenchRecord& r, const Options& o, const Scene& scene, const FormFactors& F, const std::vector<Rgb>& B);

}  // namespace hemirad
