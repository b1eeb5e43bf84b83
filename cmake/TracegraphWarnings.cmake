# Compiler warnings and sanitizers shared by every Tracegraph target.
add_library(tg_build_flags INTERFACE)
target_compile_options(tg_build_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                 -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
                                 -Wdouble-promotion -Wformat=2>)
if(TG_WARNINGS_AS_ERRORS)
  target_compile_options(tg_build_flags INTERFACE -Werror)
endif()
if(TG_SANITIZE)
  target_compile_options(tg_build_flags INTERFACE -fsanitize=address,undefined
                                                  -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(tg_build_flags INTERFACE -fsanitize=address,undefined)
endif()
