# One warning policy for all of our own targets: mo_set_warnings(<target>).
# -Werror=switch: a new expression kind fails to compile where it is not handled.
add_library(mo_warnings INTERFACE)
target_compile_options(mo_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wnon-virtual-dtor -Werror=switch -Werror=return-type
  $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>)
if(MO_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(MO_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
