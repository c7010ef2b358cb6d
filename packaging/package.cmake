# The Debian package (CPack, DEB generator): install rules beside the executable's, and the package's
# metadata. Included at the end of the top-level CMakeLists.txt. Build it with `make package`
# (amd64 from the native build, arm64 from the cross build); docs/packaging.md has the layout.
#
#   /usr/bin/m2mlat                                   (the top-level install(TARGETS ...))
#   /usr/lib/systemd/system/m2mlat-agent@.service     one agent per /etc/m2mlat/<instance>.toml
#   /usr/lib/udev/rules.d/60-m2mlat-gpio.rules        /dev/gpiochip* for the group gpio
#   /usr/libexec/m2mlat/irq-affinity                  the unit's root helper for IRQ affinity
#   /etc/m2mlat/agent.toml.example                    a commented configuration (conffile)
#   /usr/share/man/man1/m2mlat*.1.gz                  generated from the executable's --help
#   /usr/share/bash-completion/completions/m2mlat     generated from the subcommand table
#   /usr/share/doc/m2mlat/                            docs/packaging.md, docs/record-example.toml
set(M2MLAT_PACKAGING_DIR ${CMAKE_CURRENT_LIST_DIR})

install(FILES ${M2MLAT_PACKAGING_DIR}/m2mlat-agent@.service DESTINATION lib/systemd/system)
install(FILES ${M2MLAT_PACKAGING_DIR}/60-m2mlat-gpio.rules DESTINATION lib/udev/rules.d)
install(PROGRAMS ${M2MLAT_PACKAGING_DIR}/irq-affinity DESTINATION libexec/m2mlat)
install(FILES ${M2MLAT_PACKAGING_DIR}/agent.toml.example DESTINATION /etc/m2mlat)
install(FILES ${PROJECT_SOURCE_DIR}/docs/packaging.md ${PROJECT_SOURCE_DIR}/docs/record-example.toml
        DESTINATION share/doc/m2mlat)

# Man pages and bash completion: generated when installing (so when packaging), not on every build,
# by running the built executable (under the emulator when cross-compiling: the text is the same).
# The pages' date is SOURCE_DATE_EPOCH if set, else the top-level CMakeLists.txt's modification time.
option(M2MLAT_INSTALL_GENERATED_DOCS "Install man pages and bash completion generated with help2man" ON)
if(M2MLAT_INSTALL_GENERATED_DOCS)
  if(DEFINED ENV{SOURCE_DATE_EPOCH})
    set(m2mlat_doc_epoch $ENV{SOURCE_DATE_EPOCH})
  else()
    file(TIMESTAMP ${PROJECT_SOURCE_DIR}/CMakeLists.txt m2mlat_doc_epoch "%s" UTC)
  endif()
  set(m2mlat_doc_dir ${PROJECT_BINARY_DIR}/packaging-docs)
  set(m2mlat_doc_runner "")
  if(CMAKE_CROSSCOMPILING)
    set(m2mlat_doc_runner ${CMAKE_CROSSCOMPILING_EMULATOR})
  endif()
  list(JOIN m2mlat_doc_runner "\" \"" m2mlat_doc_runner_quoted)
  if(m2mlat_doc_runner)
    set(m2mlat_doc_runner_quoted "\"${m2mlat_doc_runner_quoted}\"")
  endif()
  install(CODE "
    execute_process(
      COMMAND \"${CMAKE_COMMAND}\" -E env SOURCE_DATE_EPOCH=${m2mlat_doc_epoch}
              bash \"${M2MLAT_PACKAGING_DIR}/gen-docs.sh\" \"${m2mlat_doc_dir}\" \"${PROJECT_VERSION}\"
              ${m2mlat_doc_runner_quoted} \"$<TARGET_FILE:m2mlat_exe>\"
      RESULT_VARIABLE m2mlat_doc_result)
    if(NOT m2mlat_doc_result EQUAL 0)
      message(FATAL_ERROR \"packaging/gen-docs.sh failed (\${m2mlat_doc_result})\")
    endif()")
  install(DIRECTORY ${m2mlat_doc_dir}/man1 DESTINATION share/man)
  install(FILES ${m2mlat_doc_dir}/completions/m2mlat DESTINATION share/bash-completion/completions)
endif()

# Package metadata.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME m2mlat)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR m2mlat)
set(M2MLAT_PACKAGE_MAINTAINER "m2mlat maintainers <m2mlat@localhost>"
    CACHE STRING "The Maintainer field of the Debian package")
set(CPACK_PACKAGE_CONTACT ${M2MLAT_PACKAGE_MAINTAINER})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Motion-to-Motion latency measurement for vehicle teleoperation")
set(CPACK_PACKAGE_DESCRIPTION
    "m2mlat timestamps GPIO edges in the kernel on two boards (a Hall sensor on the operator's
steering wheel and one on the vehicle's), keeps the boards' clock state, pairs cause and effect
edges into latency samples, and reports statistics with their uncertainty. The package holds the
m2mlat command, a systemd unit for the capture agent (m2mlat-agent@.service) and a udev rule that
gives the group gpio access to the GPIO character devices.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The shared libraries' packages come from dpkg-shlibdeps, for the cross build too: it reads the
# symbols files of the arm64 library packages installed through multiarch (libsqlite3-0:arm64, ...).
# adduser runs in postinst. libpq5 is loaded with dlopen (archive/libpq.hpp), which dpkg-shlibdeps
# cannot see: it is named here.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, libpq5")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "chrony, linuxptp, rt-tests")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${M2MLAT_PACKAGING_DIR}/postinst ${M2MLAT_PACKAGING_DIR}/prerm ${M2MLAT_PACKAGING_DIR}/postrm
    ${M2MLAT_PACKAGING_DIR}/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
if(CMAKE_CROSSCOMPILING)
  # CPack would ask dpkg for the host's architecture.
  if(CMAKE_SYSTEM_PROCESSOR STREQUAL aarch64)
    set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
  elseif(CMAKE_SYSTEM_PROCESSOR STREQUAL x86_64)
    set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE amd64)
  else()
    message(WARNING "no Debian architecture known for ${CMAKE_SYSTEM_PROCESSOR}: set CPACK_DEBIAN_PACKAGE_ARCHITECTURE")
  endif()
endif()
include(CPack)
