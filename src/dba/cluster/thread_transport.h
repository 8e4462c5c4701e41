// N ranks as threads of one process (cluster/transport.h): every
// distributed code path runs in one test binary, no mpirun. Messages are
// copied into per-pair mailboxes; a collective goes through rank 0 in rank
// order (so its sums are the same from run to run). A rank that aborts
// wakes every other rank, which then throws too.
//
// Thread safety: one thread per rank; the mailboxes are shared under one
// lock.
#pragma once

#include <functional>
#include <memory>

#include "dba/cluster/communicator.h"
#include "dba/cluster/transport.h"

namespace dba {

class ThreadGroup;

// Runs body(comm) on `ranks` threads, each with a Communicator of its own
// rank over in-process transport; returns when all are done. An exception
// on any rank ends the others (their waits throw) and is rethrown here (the
// first one).
void RunRanksAsThreads(int ranks, const std::function<void(Communicator& comm)>& body);

}  // namespace dba
