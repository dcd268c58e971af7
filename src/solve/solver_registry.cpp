// The solver registry: one line per family.
#include "solve/solver_registry.hpp"

#include "engine/error.hpp"

namespace hemirad {

const std::vector<const SolverDescriptor*>& solverRegistry() {
    static const std::vector<const SolverDescriptor*> solvers = [] {
        std::vector<const SolverDescriptor*> all;
        for (const std::vector<SolverDescriptor>* family : {
                 &eigenSolvers(),       // lu, cholesky, cg, bicgstab
                 &stationarySolvers(),  // jacobi, gauss-seidel, sor, southwell
             })
            for (const SolverDescriptor& d : *family) all.push_back(&d);
        return all;
    }();
    return solvers;
}

std::string solverNames() {
    std::string names = "auto";
    for (const SolverDescriptor* d : solverRegistry()) names += ", " + d->name;
    return names;
}

const SolverDescriptor& findSolver(std::string_view name) {
    for (const SolverDescriptor* d : solverRegistry())
        if (d->name == name) return *d;
    throw Error("unknown solver '" + std::string(name) + "' (" + solverNames() + ")");
}

void checkSolverName(const std::string& name) {
    if (name != "auto") findSolver(name);
}

}  // namespace hemirad
