// Several files replaced together, all or none, even when the process is
// killed (SIGKILL, a power cut) in the middle: a COLMAP model's files, a
// run's outputs. Each temporary is renamed over its file, and a journal
// says which were replaced, so that what a kill leaves is undone or finished
// by the next process that touches any of the files
// (io/stale_temporaries.h), never left half old, half new.
//
// The steps, for files F0..Fn-1 and an id (stale_temporaries.h UniqueId):
//  1. Fi.dba-old.<id>: a hard link to (or a copy of) each old file;
//  2. F0.dba-journal.<id>: per file whether it had an old version, the
//     temporary's inode, the file's and the temporary's absolute paths;
//     written whole (its last line "end") and synced;
//  3. Fi.dba-member.<id>: a symbolic link to F0's absolute path, so that
//     the journal can be found from any file;
//  4. the renames, one by one;
//  5. the commit: F0.dba-journal.<id> renamed to F0.dba-done.<id>;
//  6. per file, its old copy then its member link removed; the done file.
// Undone (a kill before 5, or a rename that fails): every file whose inode
// is its temporary's is put back (its old copy renamed over it, or, new,
// removed); the temporaries left, the old copies, the member links and the
// journal removed. Finished (a kill after 5): step 6.
//
// For tests, DBA_KILL_IN_COMMIT=N: SIGKILL after the N-th step of a
// replacement of several files: 1 the journal and links written, 2..n+1
// the renames, n+2 the commit, n+3..2n+2 each file's old copy removed.
//
// Thread safety: touches only the files it names; distinct calls may run
// at once (their ids differ).
#pragma once

#include <string>
#include <vector>

namespace dba {

struct Replacement {
  std::string tmp, file;  // a finished temporary, the file it replaces
};

// Renames each temporary over its file, all or none. Throws
// std::runtime_error naming the file that failed (and the files put back)
// after undoing everything; the temporaries are then removed too.
void ReplaceTogether(const std::vector<Replacement>& files);

// What a dead process left of the replacement `id` whose first file is
// `first_file` (io/stale_temporaries.cc finds it): undone when its journal
// is whole and not committed, finished when committed; a journal not whole
// (killed while it was written, before any rename) is removed.
void UndoOrFinishReplacement(const std::string& first_file, const std::string& id);

}  // namespace dba
