// roger: the command-line program (subcommands are added as the engine grows).
#include <cstdio>

int main() {
  std::puts("roger " ROGER_VERSION);
  return 0;
}
