// The temporaries of atomic outputs (io/atomic_output_file.h) that exist right
// now, so that SIGINT, SIGTERM and SIGHUP remove them before the process
// ends: an interrupted run leaves neither a half-written result nor its
// temporary.
//
// Thread safety: Register/Unregister from any thread; the handler only reads
// and unlinks (async-signal-safe).
#pragma once

#include <string>

namespace dba {

// Records `path` as a temporary to remove on a signal; returns a slot for
// Unregister, or -1 when all slots are taken (the path is then not cleaned
// on a signal; ordinary error paths still remove it).
int RegisterTemporary(const std::string& path);
void UnregisterTemporary(int slot);

// Installs the handler for SIGINT, SIGTERM and SIGHUP: unlink every
// registered temporary, then die of the signal as before.
void RemoveTemporariesOnSignals();

}  // namespace dba
