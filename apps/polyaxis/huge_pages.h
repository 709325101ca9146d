// Transparent huge pages for the CLI's large buffers: a 1.3M-triangle mesh touches about 300 MB,
// and faulting it in 4 KiB pages costs more than reading the file.
#pragma once

namespace polyaxis::app {

// When an argument names a file of 16 MiB or more or the command is `plan` (whose program and its
// read-back run to hundreds of MB whatever the mesh's size), the kernel gives huge pages on request only
// (transparent_hugepage "madvise", Debian's default) and glibc's malloc has not been told either
// way, re-executes this program with GLIBC_TUNABLES glibc.malloc.hugetlb=1 added, so that malloc
// asks for them (inspect of a 1.3M-triangle mesh: 608 -> 513 ms; the re-execution costs about
// 4 ms). Returns if that is not needed or not possible; the program then runs as it is.
void use_huge_pages(char** argv);

}  // namespace polyaxis::app
