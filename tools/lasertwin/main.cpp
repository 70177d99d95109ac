// lasertwin: digital twin of a compact laser-line scanner. See README.md.
#include <iostream>
#include <map>

#include "core/error.h"
#include "core/heap_reuse.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {
std::map<std::string, AddCommand>& Registry() {
  static std::map<std::string, AddCommand> registry;
  return registry;
}
}  // namespace

CommandRegistrar::CommandRegistrar(const std::string& name, AddCommand add) {
  Registry().emplace(name, std::move(add));
}
}  // namespace lt::cli

int main(int argc, char** argv) {
  lt::RetainFreedMemory();
  CLI::App app{"lasertwin: laser-line scanner simulator and measurement pipeline"};
  app.require_subcommand(1);
  for (auto& [name, add] : lt::cli::Registry()) add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const lt::InputError& e) {
    std::cerr << "lasertwin: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "lasertwin: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
