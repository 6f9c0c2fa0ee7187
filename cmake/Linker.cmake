# LLVM's linker where the compiler can use it: it links the ~60 test executables and the tools
# about three times faster than GNU ld (2.4-3.2 s against 0.9-1.0 s for one sanitized test
# executable), which is most of a build's serial tail. The program is the same.
option(DECALCOMP_LLD "Link with lld when the compiler accepts -fuse-ld=lld" ON)
if(DECALCOMP_LLD)
  include(CheckLinkerFlag)
  check_linker_flag(CXX -fuse-ld=lld DECALCOMP_LINKER_LLD)
  if(DECALCOMP_LINKER_LLD)
    add_link_options(-fuse-ld=lld)
  endif()
endif()
