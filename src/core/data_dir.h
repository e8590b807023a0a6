// Where pgt's shipped files are (shaders, analysis scripts, scenes, docs): the `share/pgt`
// folder found beside the running binary, so that a build tree, an install prefix and the
// Python module all find their own (docs/install.md). Nothing is compiled in.
#pragma once

#include <string>

namespace pgt {

// The data folder, searched in this order:
//   1. $PGT_DATA_DIR, when set;
//   2. `share/pgt` in the folder of the binary that holds this code (the pgt executable, a
//      test binary or the Python module's shared object) or in one of its up to four
//      parents: PREFIX/bin/pgt -> PREFIX/share/pgt; PREFIX/lib/python3/dist-packages/pgt/
//      _pgt*.so -> PREFIX/share/pgt; a build tree's build/src/pgt -> build/share/pgt (CMake
//      links that folder's entries to the sources at configure time).
// A candidate counts when it holds `shaders/`. Throws InputError naming what was searched
// when none does.
std::string dataDir();

// A file pgt installs beside its binaries, `relative` to a folder searched as dataDir()
// searches (the folder of the binary holding this code and up to four parents), e.g.
// "lib/pgt/pgt_image.so": PREFIX/bin/pgt -> PREFIX/lib/pgt/..., build/src/pgt ->
// build/lib/pgt/...; $envOverride when set. Throws InputError naming what was searched when
// none holds it.
std::string installedFile(const std::string& relative, const char* envOverride);

// One entry of the data folder, with its own override: `subdir` of dataDir() unless the
// environment variable `envOverride` is set (PGT_SHADER_DIR, PGT_ANALYSIS_DIR).
std::string dataSubdir(const std::string& subdir, const char* envOverride);

}  // namespace pgt
