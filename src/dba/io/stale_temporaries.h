// What a dba process that died without cleaning up (SIGKILL, a power cut)
// left beside an output file FILE, and putting it right:
//  - FILE.tmp.<pid>: a temporary being written (io/atomic_output_file.h):
//    removed;
//  - FILE.dba-old.<pid>: the old FILE, kept while several outputs were being
//    replaced together: that replacement was not finished, so it is undone,
//    the old file put back over FILE (a COLMAP model is then the old model
//    whole, never half old and half new).
// Only what a dead process left is touched: <pid> is no process on this
// machine, and (a temporary) no process holds its lock, so a live writer's
// files, here or on another machine sharing the directory, are left alone.
//
// Thread safety: touches only the files it names.
#pragma once

#include <string>

namespace dba {

std::string TemporaryName(const std::string& file);  // FILE.tmp.<this pid>
std::string BackupName(const std::string& file);     // FILE.dba-old.<this pid>

// Takes the lock a live temporary holds (flock on a descriptor of its own,
// kept open while the temporary exists); returns it, -1 where the system
// has no locks.
int LockTemporary(const std::string& tmp);

// Removes the stale temporaries of `file` and puts back its stale backups.
// Returns how many it found. Errors are ignored: what cannot be removed is
// left for the next time.
int RecoverStaleTemporaries(const std::string& file);

}  // namespace dba
