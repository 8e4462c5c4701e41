// What a dba process that died without cleaning up (SIGKILL, a power cut)
// left beside an output file FILE, and putting it right. Every name ends in
// an id "<pid>.<n>": the writer's pid and a number of its own, one per call,
// so two threads of one process writing one file never share a name.
//  - FILE.tmp.<id>: a temporary being written (io/atomic_output_file.h):
//    removed;
//  - FILE.dba-journal.<id>, FILE.dba-done.<id>, FILE.dba-member.<id> and
//    FILE.dba-old.<id>: a replacement of several files together that was
//    not finished (io/replace_together.h): undone (every file of it put back
//    as it was) when it had not reached its commit, else finished (the old
//    copies removed); a COLMAP model, or a run's outputs, is then old whole
//    or new whole, never a mix.
// Only what a dead process left is touched: <pid> is no process on this
// machine, and (a temporary) no process holds its lock, so a live writer's
// files, here or on another machine sharing the directory, are left alone.
// Names ending in a bare "<pid>" (older versions') are recognised too.
//
// Thread safety: UniqueId from any thread; the rest touch only the files
// they name.
#pragma once

#include <string>

namespace dba {

// "<pid>.<n>", a different n at every call in this process.
std::string UniqueId();
std::string TemporaryName(const std::string& file);  // FILE.tmp.<UniqueId()>

// Takes the lock a live temporary holds (flock on a descriptor of its own,
// kept open while the temporary exists); returns it, -1 where the system
// has no locks.
int LockTemporary(const std::string& tmp);

// Puts right what dead processes left beside `file`: removes its stale
// temporaries, undoes or finishes the replacements it took part in (and
// with it every other file of them, wherever they are). Returns how many
// leftovers it found. Errors are ignored: what cannot be removed is left
// for the next time.
int RecoverStaleTemporaries(const std::string& file);

}  // namespace dba
