// columns.hpp: the kernel's tables that the scripts read, by name, defined once. Each table is
// a list of columns (an enum for the kernel's code, a name for the scripts'); the scripts ask
// for a column's index by its name, contactKernelColumn(table, name), and never use a bare
// number (bindings.cpp). The names are those of the output files' columns and summary keys.
//   nodal          a node's row of contactKernelNodal (contact.txt, contact_nodes_history.txt,
//                  the end-of-run checks)
//   record         a step's record, contactKernelRecord (history.txt, contact_history.txt)
//   history        a step's row of the history array of contactKernelHistory: t, the solver's
//                  iterations and residual, then the record's columns
//   solver_info    the outcome of a contact solve (contactKernelNewton, ...FixedPoint, ...Step)
//   safeguard_info what contactNewtonStart and contactNewtonSafeguard report
//   counters       the run's counts of contactKernelCounters (summary.txt's keys)
#ifndef CONTACTKERNEL_COLUMNS_HPP
#define CONTACTKERNEL_COLUMNS_HPP
#include <string>
#include "contactlaw.hpp"

namespace contactkernel {

// X(enum name, column name, written as an integer)
#define CONTACTKERNEL_NODAL_COLUMNS(X)                                                                 \
  X(NodalVNu, "v_nu", false) X(NodalVTau, "v_tau", false) X(NodalPNu, "p_nu", false)                   \
  X(NodalLambdaNu, "lambda_nu", false) X(NodalLambdaTau, "lambda_tau", false)                          \
  X(NodalNormalStatus, "normal_status", true) X(NodalTangentialStatus, "tangential_status", true)      \
  X(NodalFrictionBound, "friction_bound", false) X(NodalForceScale, "force_scale", false)              \
  X(NodalZone, "zone", true) X(NodalVTau2, "v_tau2", false) X(NodalLambdaTau2, "lambda_tau2", false)   \
  X(NodalDampedResponse, "damped_response", false) X(NodalG, "g", false) X(NodalDampingSlope, "damping_slope", false)

#define CONTACTKERNEL_RECORD_COLUMNS(X)                                                                \
  X(RecordKinetic, "kinetic", false) X(RecordElastic, "elastic", false)                                \
  X(RecordNumericalDissipation, "numerical_dissipation", false)                                        \
  X(RecordViscousDissipation, "viscous_dissipation", false)                                            \
  X(RecordContactDissipation, "contact_dissipation", false) X(RecordExternalWork, "external_work", false) \
  X(RecordEnergyResidual, "energy_residual", false) X(RecordKineticJump, "kinetic_jump", false)        \
  X(RecordElasticJump, "elastic_jump", false) X(RecordNormalForce, "normal_force", false)              \
  X(RecordTangentialForce, "tangential_force", false)                                                  \
  X(RecordZone0, zoneColumn(0), true) X(RecordZone1, zoneColumn(1), true) X(RecordZone2, zoneColumn(2), true) \
  X(RecordZone3, zoneColumn(3), true) X(RecordZone4, zoneColumn(4), true)                              \
  X(RecordXB, "x_B", false) X(RecordXC, "x_C", false) X(RecordTangentialForce2, "tangential_force2", false) \
  X(RecordXBEstimate, "x_B_estimate", false) X(RecordXCEstimate, "x_C_estimate", false)             \
  X(RecordBoundariesB, "boundaries_B", true) X(RecordBoundariesC, "boundaries_C", true)

#define CONTACTKERNEL_HISTORY_COLUMNS(X)                                                               \
  X(HistoryT, "t", false) X(HistoryIterations, "iterations", true) X(HistoryResidual, "residual", false)

#define CONTACTKERNEL_SOLVER_INFO_COLUMNS(X)                                                           \
  X(InfoResidual, "residual", false) X(InfoIterations, "iterations", true)                             \
  X(InfoUnresolved, "unresolved", true) X(InfoStalled, "stalled", true)

#define CONTACTKERNEL_SAFEGUARD_INFO_COLUMNS(X)                                                        \
  X(SafeguardResidual, "residual", false) X(SafeguardStep, "step", false) X(SafeguardMerit, "merit", false) \
  X(SafeguardUnresolved, "unresolved", true)

#define CONTACTKERNEL_COUNTER_COLUMNS(X)                                                               \
  X(CounterFallbacks, "newton_fallbacks", true) X(CounterSweeps, "fixed_point_sweeps", true)           \
  X(CounterFactorizations, "newton_factorizations", true)                                              \
  X(CounterCorrections, "newton_low_rank_corrections", true) X(CounterRefinements, "newton_refinements", true) \
  X(CounterCuts, "newton_shortened_steps", true) X(CounterHalvings, "augmentation_halvings", true)     \
  X(CounterRetries, "newton_retries", true) X(CounterWatchdogs, "newton_watchdogs", true)              \
  X(CounterWatchdogReturns, "newton_watchdog_returns", true)

// the record's zone counts: zone_NAME, NAME the law's (contactlaw.hpp, zoneNames), in zone order
const char *zoneColumn(int zone);

#define CONTACTKERNEL_ENUM(id, name, integer) id,
enum NodalColumn { CONTACTKERNEL_NODAL_COLUMNS(CONTACTKERNEL_ENUM) nodalColumnCount };
enum RecordColumn { CONTACTKERNEL_RECORD_COLUMNS(CONTACTKERNEL_ENUM) recordColumnCount };
// the history row: its own columns, then the record's from historyRecordStart on
enum HistoryColumn { CONTACTKERNEL_HISTORY_COLUMNS(CONTACTKERNEL_ENUM) historyRecordStart,
                     historyColumnCount = historyRecordStart + recordColumnCount };
enum SolverInfoColumn { CONTACTKERNEL_SOLVER_INFO_COLUMNS(CONTACTKERNEL_ENUM) solverInfoColumnCount };
enum SafeguardInfoColumn { CONTACTKERNEL_SAFEGUARD_INFO_COLUMNS(CONTACTKERNEL_ENUM) safeguardInfoColumnCount };
enum CounterColumn { CONTACTKERNEL_COUNTER_COLUMNS(CONTACTKERNEL_ENUM) counterColumnCount };
#undef CONTACTKERNEL_ENUM
static_assert(RecordZone4 - RecordZone0 + 1 == contactlaw::zoneCount, "one record column per zone of contactlaw.hpp");

struct Column { const char *name; bool integer; };
// the columns of a table (nullptr if there is no such table), and how many
const Column *columnsOf(const std::string &table, int &count);
// the index of a column, -1 if the table has none of that name
int columnIndex(const std::string &table, const std::string &name);
// the names of the tables, "nodal, record, ..." (messages)
std::string tableNames();

}  // namespace contactkernel
#endif
