// pcl_patchdict — command-line front end (placeholder until the subcommands land).
#include <cstdio>
int main() { std::fprintf(stderr, "pcl_patchdict: no subcommands yet\n"); return 2; }
