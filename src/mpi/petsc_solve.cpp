// Distributed solve with PETSc on F's rows where the ranks hold them (petsc_rows.hpp: the renumbering
// that gives each rank a contiguous range), solving P (I - R F) P^T (P B) = P E: the same system, the
// same residuals.
#include "mpi/petsc_solve.hpp"

#include "cli/options.hpp"
#include "mpi/petsc_rows.hpp"

#include <petscksp.h>

#include <chrono>
#include <cmath>
#include <sstream>

namespace hemirad::mpi {
namespace {

struct Channel {
    std::vector<double> rho, E;  // this rank's rows, in new order
    std::string names;
    SolveReport report;
    std::vector<double> B;       // all patches, on rank 0
};

/// CG's operator without its per-channel diagonal: S = -(G + G^T) / 2 with G = diag(A) F, the area-
/// weighted F symmetrised as one process symmetrises it (eigen_solvers.cpp). G is kept for residuals.
struct SymmetricPart {
    OwnedMat G, S;
};

void buildSymmetricPart(SymmetricPart& part, const Scene& scene, const DistributedFormFactors& F, const Layout& layout,
                        const Preallocation& counts) {
    part.G.mat = areaWeightedRows(scene, F, layout, counts);
    OwnedMat Gt;
    check(MatTranspose(part.G.mat, MAT_INITIAL_MATRIX, &Gt.mat), "MatTranspose");
    check(MatDuplicate(part.G.mat, MAT_COPY_VALUES, &part.S.mat), "MatDuplicate");
    check(MatAXPY(part.S.mat, 1.0, Gt.mat, DIFFERENT_NONZERO_PATTERN), "MatAXPY");
    check(MatScale(part.S.mat, -0.5), "MatScale");
}

}  // namespace

const std::vector<std::string>& distributedSolverNames() {
    static const std::vector<std::string> names = {"bicgstab", "cg", "jacobi"};
    return names;
}

void checkDistributedSolver(const std::string& name) {
    if (name == "auto") return;
    for (const std::string& s : distributedSolverNames())
        if (s == name) return;
    throw UsageError("--solver " + name + " does not run across MPI ranks; the distributed solve takes auto, bicgstab, "
                     "cg or jacobi (PETSc)");
}

namespace {

/// "auto" as bicgstab; the solver and the tolerance checked.
std::string checkedSolverName(const SolverOptions& options) {
    const std::string name = options.solver == "auto" ? "bicgstab" : options.solver;
    checkDistributedSolver(name);
    if (!(options.tolerance > 0.0) || options.tolerance >= 1.0)
        throw Error("solve: tolerance must be in (0, 1), got " + std::to_string(options.tolerance));
    return name;
}

/// Solves (I - R F) B = E for each channel (rho and E on this rank's rows, in the layout's order):
/// each channel's B in patch order on rank 0, or on every rank with `everywhere`. Collective.
void solveChannels(const Context& context, const Scene& scene, const DistributedFormFactors& F, const Layout& layout,
                   std::vector<Channel>& channels, const std::string& name, const SolverOptions& options,
                   bool everywhere) {
    const std::size_t n = scene.size();
    const PetscInt m = layout.end - layout.begin;
    const Preallocation counts = preallocationOf(F, layout);

    const bool cg = name == "cg";
    SymmetricPart symmetric;
    if (cg) buildSymmetricPart(symmetric, scene, F, layout, counts);
    const std::size_t local = layout.mine.size();

    // The operator for reflectances rho (this rank's rows): I - R F, or for cg K = diag(A / rho) + S
    // with the black patches' (rho = 0: B = E) rows and columns taken out (the identity there).
    auto operatorFor = [&](const std::vector<double>& rho) {
        Mat A;
        if (cg) {
            check(MatDuplicate(symmetric.S.mat, MAT_COPY_VALUES, &A), "MatDuplicate");
            Vec d;
            check(MatCreateVecs(A, &d, nullptr), "MatCreateVecs");
            for (std::size_t k = 0; k < local; ++k) {
                const double area = scene.patches[layout.mine[k]].area;
                check(VecSetValue(d, layout.begin + PetscInt(k), rho[k] > 0.0 ? area / rho[k] : 1.0, INSERT_VALUES),
                      "VecSetValue");
            }
            check(VecAssemblyBegin(d), "VecAssemblyBegin");
            check(VecAssemblyEnd(d), "VecAssemblyEnd");
            const PetscErrorCode code = MatDiagonalSet(A, d, ADD_VALUES);
            VecDestroy(&d);
            check(code, "MatDiagonalSet");
            std::vector<PetscInt> black;
            for (std::size_t k = 0; k < local; ++k)
                if (!(rho[k] > 0.0)) black.push_back(layout.begin + PetscInt(k));
            check(MatZeroRowsColumns(A, PetscInt(black.size()), black.data(), 1.0, nullptr, nullptr), "MatZeroRowsColumns");
        } else {
            std::vector<double> one(local, 1.0), minusRho(local);
            for (std::size_t k = 0; k < local; ++k) minusRho[k] = -rho[k];
            A = rowsMatrix(F, layout, n, counts, one, minusRho);
        }
        return A;
    };
    Mat A = nullptr;
    KSP ksp = nullptr;
    const std::vector<double>* sameRho = nullptr;  // the rho A was built for

    for (Channel& ch : channels) {
        const auto t0 = std::chrono::steady_clock::now();
        ch.report.solver = name + " (PETSc, " + std::to_string(context.size()) + " ranks)";
        ch.report.channels = ch.names;
        double normE = 0, localE = 0;
        for (double e : ch.E) localE += e * e;
        MPI_Allreduce(&localE, &normE, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
        normE = std::sqrt(normE);
        std::vector<double> B(context.root() || everywhere ? n : 0, 0.0);  // filled on rank 0 only, or everywhere
        if (normE == 0.0) {
            ch.report.converged = true;
            ch.report.note = "no emission in this channel";
        } else {
            Vec b, x, r;
            std::vector<double> rhs(ch.E);  // this rank's right-hand side
            if (cg)
                for (std::size_t k = 0; k < local; ++k)
                    if (ch.rho[k] > 0.0) rhs[k] = scene.patches[layout.mine[k]].area / ch.rho[k] * ch.E[k];
            // The operator and its solver depend on rho alone: built once for the channels that share it
            // (a thermal model's IR band and its isothermal nodes' bands).
            // (Each rank compares its own rows: agreed, as the rebuild is collective.)
            int rebuild = !A || !sameRho || ch.rho != *sameRho ? 1 : 0;
            MPI_Allreduce(MPI_IN_PLACE, &rebuild, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
            if (rebuild) {
                KSPDestroy(&ksp);
                MatDestroy(&A);
                A = operatorFor(ch.rho);
                PC pc;
                check(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
                check(KSPSetOperators(ksp, A, A), "KSPSetOperators");
                check(KSPGetPC(ksp, &pc), "KSPGetPC");
                check(PCSetType(pc, PCJACOBI), "PCSetType");
                if (name == "bicgstab") {
                    check(KSPSetType(ksp, KSPBCGS), "KSPSetType");
                    check(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");  // the norm watched is the true residual's
                } else if (cg) {
                    check(KSPSetType(ksp, KSPCG), "KSPSetType");
                } else {
                    check(KSPSetType(ksp, KSPRICHARDSON), "KSPSetType");
                }
                check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
                // rtol against ||b|| = ||E|| (PETSc's default test), starting from B = E.
                check(KSPSetTolerances(ksp, options.tolerance, 0.0, PETSC_DEFAULT, options.maxIterations),
                      "KSPSetTolerances");
                check(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
                sameRho = &ch.rho;
            }
            check(MatCreateVecs(A, &x, &b), "MatCreateVecs");
            check(VecDuplicate(b, &r), "VecDuplicate");
            for (PetscInt k = 0; k < m; ++k) {
                check(VecSetValue(b, layout.begin + k, rhs[std::size_t(k)], INSERT_VALUES), "VecSetValue");
                check(VecSetValue(x, layout.begin + k, ch.E[std::size_t(k)], INSERT_VALUES), "VecSetValue");
            }
            for (Vec v : {b, x}) {
                check(VecAssemblyBegin(v), "VecAssemblyBegin");
                check(VecAssemblyEnd(v), "VecAssemblyEnd");
            }
            if (cg) {
                // Black patches (rho = 0) left the system (operatorFor), B = E there. Row i's terms
                // A_i F_ij E_j of black columns j join b_i unsymmetrised, as one process moves them: the
                // pair's mean would halve the light of a black emitter whose own row is not computed.
                std::vector<PetscInt> black;
                for (std::size_t k = 0; k < local; ++k)
                    if (!(ch.rho[k] > 0.0)) black.push_back(layout.begin + PetscInt(k));
                check(VecSet(r, 0.0), "VecSet");
                for (PetscInt row : black)
                    check(VecSetValue(r, row, ch.E[std::size_t(row - layout.begin)], INSERT_VALUES), "VecSetValue");
                check(VecAssemblyBegin(r), "VecAssemblyBegin");
                check(VecAssemblyEnd(r), "VecAssemblyEnd");
                Vec moved;
                check(VecDuplicate(b, &moved), "VecDuplicate");
                check(MatMult(symmetric.G.mat, r, moved), "MatMult");
                check(VecAXPY(b, 1.0, moved), "VecAXPY");
                VecDestroy(&moved);
                for (PetscInt row : black)
                    check(VecSetValue(b, row, ch.E[std::size_t(row - layout.begin)], INSERT_VALUES), "VecSetValue");
                check(VecAssemblyBegin(b), "VecAssemblyBegin");
                check(VecAssemblyEnd(b), "VecAssemblyEnd");
            }
            check(KSPSolve(ksp, b, x), "KSPSolve");
            KSPConvergedReason reason;
            PetscInt iterations = 0;
            check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
            check(KSPGetIterationNumber(ksp, &iterations), "KSPGetIterationNumber");
            // The residual of the system the user posed, measured, not the solver's running estimate.
            PetscReal residual = 0;
            check(MatMult(A, x, r), "MatMult");
            check(VecAYPX(r, -1.0, b), "VecAYPX");
            check(VecNorm(r, NORM_2, &residual), "VecNorm");
            ch.report.iterations = int(iterations);
            if (cg) {
                // The symmetric system's own residual, then that of I - R F: E - B + R F B, F B = (G B) / A.
                PetscReal normB = 0;
                check(VecNorm(b, NORM_2, &normB), "VecNorm");
                ch.report.residual = normB > 0 ? double(residual) / double(normB) : 0.0;
                check(MatMult(symmetric.G.mat, x, r), "MatMult");
                const PetscScalar *gx = nullptr, *xs = nullptr;
                check(VecGetArrayRead(r, &gx), "VecGetArrayRead");
                check(VecGetArrayRead(x, &xs), "VecGetArrayRead");
                double sum = 0, total = 0;
                for (std::size_t k = 0; k < local; ++k) {
                    const double area = scene.patches[layout.mine[k]].area;
                    const double e = ch.E[k] - xs[k] + (ch.rho[k] > 0.0 ? ch.rho[k] * gx[k] / area : 0.0);
                    sum += e * e;
                }
                VecRestoreArrayRead(x, &xs);
                VecRestoreArrayRead(r, &gx);
                MPI_Allreduce(&sum, &total, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
                ch.report.residualOriginal = std::sqrt(total) / normE;
                // As in one process: converged on the symmetrised system means nothing for a non-reciprocal F.
                const double limit = std::max(10.0 * options.tolerance, 1e-6);
                ch.report.converged = reason > 0 && ch.report.residualOriginal <= limit;
                if (reason > 0 && !ch.report.converged) {
                    std::ostringstream note;
                    note << "the symmetrised system converged (residual " << ch.report.residual
                         << ") but the residual on I - R F is " << ch.report.residualOriginal << " > " << limit
                         << ": F is not reciprocal enough for the symmetric form; use bicgstab or jacobi, or an F made "
                            "reciprocal in one process (--enforce-reciprocity)";
                    ch.report.note = note.str();
                }
            } else {
                ch.report.residual = ch.report.residualOriginal = double(residual) / normE;
                ch.report.converged = reason > 0 && ch.report.residual <= std::max(10.0 * options.tolerance, 1e-12);
            }
            if (reason <= 0) {
                const char* why = nullptr;
                KSPGetConvergedReasonString(ksp, &why);
                ch.report.note = std::string("PETSc: ") + (why ? why : "not converged");
            }
            // B to rank 0 (or to every rank), back in patch order.
            VecScatter toZero;
            Vec all;
            if (everywhere) check(VecScatterCreateToAll(x, &toZero, &all), "VecScatterCreateToAll");
            else check(VecScatterCreateToZero(x, &toZero, &all), "VecScatterCreateToZero");
            check(VecScatterBegin(toZero, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
            check(VecScatterEnd(toZero, x, all, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
            if (context.root() || everywhere) {
                const PetscScalar* values0 = nullptr;
                check(VecGetArrayRead(all, &values0), "VecGetArrayRead");
                for (std::size_t i = 0; i < n; ++i) B[i] = values0[layout.perm[i]];
                check(VecRestoreArrayRead(all, &values0), "VecRestoreArrayRead");
            }
            VecScatterDestroy(&toZero);
            VecDestroy(&all);
            VecDestroy(&r);
            VecDestroy(&x);
            VecDestroy(&b);
        }
        ch.B = std::move(B);
        ch.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    KSPDestroy(&ksp);
    MatDestroy(&A);
}

}  // namespace

Radiosity solveDistributed(const Context& context, const Scene& scene, const DistributedFormFactors& F,
                           const SolverOptions& options) {
    const std::size_t n = scene.size();
    const std::string name = checkedSolverName(options);
    for (std::size_t i = 0; i < n; ++i)
        if ((scene.patches[i].rho > 0.0).any() && F.owner[i] < 0)
            throw Error("solve: row " + std::to_string(i) + " of F was not computed (the patch was black then) "
                        "but its reflectance is now > 0; recompute F or its missing rows");
    const Layout layout = layoutOf(context, F.owner);

    // Distinct channels (identical rho and E over all patches are solved once), as in one process.
    static const char* kNames[3] = {"r", "g", "b"};
    std::vector<Channel> channels;
    std::array<int, 3> channelOf{};
    for (int c = 0; c < 3; ++c) {
        int same = -1;
        // Channel d was made from the colour its name starts with.
        for (std::size_t d = 0; d < channels.size() && same < 0; ++d) {
            const int first = channels[d].names[0] == 'r' ? 0 : channels[d].names[0] == 'g' ? 1 : 2;
            bool equal = true;
            for (std::size_t i = 0; i < n && equal; ++i)
                equal = scene.patches[i].rho[c] == scene.patches[i].rho[first] &&
                        scene.patches[i].emission[c] == scene.patches[i].emission[first];
            if (equal) same = int(d);
        }
        if (same >= 0) {
            channels[std::size_t(same)].names += kNames[c];
        } else {
            Channel ch;
            ch.names = kNames[c];
            for (PatchId i : layout.mine) {
                ch.rho.push_back(scene.patches[i].rho[c]);
                ch.E.push_back(scene.patches[i].emission[c]);
            }
            channels.push_back(std::move(ch));
            same = int(channels.size() - 1);
        }
        channelOf[c] = same;
    }

    solveChannels(context, scene, F, layout, channels, name, options, false);

    Radiosity result;
    for (Channel& ch : channels) {
        const SolveReport& r = ch.report;
        checkConverged(r, options);
        result.reports.push_back(r);
    }
    if (context.root()) {
        result.B.assign(n, Rgb::Zero());
        for (int c = 0; c < 3; ++c)
            for (std::size_t i = 0; i < n; ++i) result.B[i][c] = channels[std::size_t(channelOf[c])].B[i];
    }
    return result;
}

BandSolution solveBandsDistributed(const Context& context, const Scene& scene, const DistributedFormFactors& F,
                                   const std::vector<Band>& bands, const SolverOptions& options) {
    const std::size_t n = scene.size();
    const std::string name = checkedSolverName(options);
    for (const Band& band : bands)
        if (band.rho.size() != n || band.source.size() != n)
            throw Error("solve: band '" + band.name + "' has " + std::to_string(band.rho.size()) + " reflectances for " +
                        std::to_string(n) + " patches");
    for (std::size_t i = 0; i < n; ++i)
        for (const Band& band : bands)
            if (band.rho[i] > 0.0 && F.owner[i] < 0)
                throw Error("solve: row " + std::to_string(i) + " of F was not computed but band '" + band.name +
                            "' reflects there; recompute F or its missing rows");
    const Layout layout = layoutOf(context, F.owner);

    // Distinct bands (identical rho and source) once, as solveBands does.
    std::vector<Channel> channels;
    std::vector<std::size_t> channelOf(bands.size());
    std::vector<std::size_t> firstBand;
    std::vector<std::vector<std::string>> namesOf;
    for (std::size_t k = 0; k < bands.size(); ++k) {
        std::size_t same = channels.size();
        for (std::size_t d = 0; d < channels.size() && same == channels.size(); ++d)
            if (bands[firstBand[d]].rho == bands[k].rho && bands[firstBand[d]].source == bands[k].source) same = d;
        if (same < channels.size()) {
            namesOf[same].push_back(bands[k].name);
        } else {
            Channel ch;
            namesOf.push_back({bands[k].name});
            for (PatchId i : layout.mine) {
                ch.rho.push_back(bands[k].rho[i]);
                ch.E.push_back(bands[k].source[i]);
            }
            channels.push_back(std::move(ch));
            firstBand.push_back(k);
        }
        channelOf[k] = same;
    }

    for (std::size_t d = 0; d < channels.size(); ++d) channels[d].names = joinBandNames(namesOf[d]);
    solveChannels(context, scene, F, layout, channels, name, options, true);

    BandSolution result;
    for (const Channel& ch : channels) {
        checkConverged(ch.report, options);
        result.reports.push_back(ch.report);
    }
    result.X.resize(bands.size());
    for (std::size_t k = 0; k < bands.size(); ++k) result.X[k] = channels[channelOf[k]].B;
    return result;
}

}  // namespace hemirad::mpi
