# The manual page (help2man, from the CLI's own --help; tools/make-man.sh) and bash completion
# (tools/completion/decalcomp.bash), installed where man and bash-completion look.
find_program(DECALCOMP_HELP2MAN help2man)
if(DECALCOMP_HELP2MAN)
  set(DECALCOMP_MAN_PAGE ${CMAKE_BINARY_DIR}/man/decalcomp.1)
  add_custom_command(OUTPUT ${DECALCOMP_MAN_PAGE}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/man
    COMMAND sh ${CMAKE_SOURCE_DIR}/tools/make-man.sh $<TARGET_FILE:decalcomp> ${DECALCOMP_MAN_PAGE}
    DEPENDS decalcomp ${CMAKE_SOURCE_DIR}/tools/make-man.sh VERBATIM)
  add_custom_target(decalcomp_man ALL DEPENDS ${DECALCOMP_MAN_PAGE})
  install(FILES ${DECALCOMP_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "help2man not found: no manual page (tools/install-deps.sh installs it)")
endif()
install(FILES ${CMAKE_SOURCE_DIR}/tools/completion/decalcomp.bash
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME decalcomp)
