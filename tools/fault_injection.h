// The command-line program's fault injection for the test suite; see
// fault_injection.cc.
#pragma once

// Installs the fault hook when DBA_INJECT_FAULT is set.
void InstallFaultInjectionFromEnvironment();
