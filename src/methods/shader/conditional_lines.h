// A shader's lines as its preprocessor will see them, for pgt's own line-wise passes over a
// user's file (#include expansion and collection, #pragma once, the #version line): comments
// blanked, and each line judged active, skipped or unknown under the file's #if, #ifdef,
// #ifndef, #elif, #else and #endif. pgt decides what it can be sure of (a number, defined()
// of a name the entry or the file defines or that nothing defines) and calls the rest
// unknown: a compiler's predefined names (GL_*, __*) and pgt's own (PGT_*) are never assumed.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pgt {

// `text` with its // and /* */ comments replaced by spaces, every line break kept, so that
// line n of the result is line n of the text.
std::string blankComments(const std::string& text);

enum class Branch { Active, Skipped, Unknown };

class ConditionalLines {
  public:
    // `defines`: names defined before the text (the entry's "defines"); `knowsDefines` false:
    // nothing is known of any name (only numbers decide).
    explicit ConditionalLines(const std::vector<std::pair<std::string, std::string>>& defines = {},
                              bool knowsDefines = true);
    // The branch of the next line (comments blanked), then the line's own effect: a
    // conditional directive is judged in the branch around it, #define and #undef counted
    // where they are not skipped.
    Branch next(const std::string& line);
    // A new file, included from a line in branch `from`: its lines lie in that branch, its
    // own conditionals start at the top (what it defines stays known).
    void enterFile(Branch from = Branch::Active) { files_.push_back({from, {}, 0, 0}); }
    void leaveFile() { files_.pop_back(); }

  private:
    enum class Known { No, Yes, Maybe };
    struct Group {
        Branch branch = Branch::Active;  // of the current arm
        bool taken = false;              // an earlier arm is certainly taken
        bool unsure = false;             // an earlier arm is unknown
    };
    struct File {
        Branch from = Branch::Active;  // the include line's branch
        std::vector<Group> groups;     // its open conditionals, innermost last
        int skipped = 0, unknown = 0;  // how many of them are in such an arm (counted)
    };
    Branch evaluate(const std::string& expr) const;
    Branch here() const;  // the branch the current line lies in
    Known defined(const std::string& name) const;
    void count(File& f, const Group& g, int sign) const;
    std::map<std::string, Known> names_;
    bool knowsDefines_;
    std::vector<File> files_{File{}};
};

}  // namespace pgt
