// The subcommand table. Add a subcommand by writing cmd_<name>.cpp and one line here.
#include <array>

#include "m2mlat/cli/command.hpp"

namespace m2mlat::cli {

Runner attach_help(CLI::App& sub);
Runner attach_demo(CLI::App& sub);
Runner attach_pair(CLI::App& sub);
Runner attach_stats(CLI::App& sub);
Runner attach_simulate(CLI::App& sub);
Runner attach_import(CLI::App& sub);
Runner attach_merge(CLI::App& sub);
Runner attach_export(CLI::App& sub);
Runner attach_record(CLI::App& sub);
Runner attach_report(CLI::App& sub);
Runner attach_agent(CLI::App& sub);
Runner attach_pulse(CLI::App& sub);
Runner attach_led(CLI::App& sub);
Runner attach_gyro(CLI::App& sub);
Runner attach_doctor(CLI::App& sub);
Runner attach_collect(CLI::App& sub);
Runner attach_watch(CLI::App& sub);
Runner attach_clock(CLI::App& sub);
Runner attach_setup(CLI::App& sub);
Runner attach_schedtest(CLI::App& sub);
Runner attach_synctest(CLI::App& sub);
Runner attach_onsettest(CLI::App& sub);
Runner attach_budget(CLI::App& sub);
Runner attach_packets(CLI::App& sub);
Runner attach_archive(CLI::App& sub);
Runner attach_mark(CLI::App& sub);
Runner attach_bag(CLI::App& sub);

namespace {
constexpr std::array kCommands{
    Command{"demo", "Simulate a campaign of several scenarios and check the results against the truth", &attach_demo},
    Command{"simulate", "Run the simulated rig into a store or into per-node files with the truth", &attach_simulate},
    Command{"pair", "Pair cause and effect edges into latency samples", &attach_pair},
    Command{"stats", "Latency statistics per scenario, from stores or data files", &attach_stats},
    Command{"import", "Read the reference rig's files or m2mlat's own into a store", &attach_import},
    Command{"merge", "Join per-board stores into a campaign store (offline; idempotent)", &attach_merge},
    Command{"export", "Write a store's events, or its pairs, as CSV or JSON Lines", &attach_export},
    Command{"record", "Record one node's edges (GPIO, kernel log or simulated) into a store", &attach_record},
    Command{"pulse", "Toggle an output line on a fixed schedule for the synchronisation test", &attach_pulse},
    Command{"led", "Switch the glass-to-glass LED (schedule, commands or input edges) and record each switch", &attach_led},
    Command{"gyro", "Record a gyroscope's raw angular-rate trace (MPU-6050 on /dev/i2c-N) into a file", &attach_gyro},
    Command{"doctor", "Check this board for capture and say what to fix", &attach_doctor},
    Command{"collect", "Pull every agent into one campaign store, live and exactly once", &attach_collect},
    Command{"watch", "Live statistics and dashboard of a store another process is filling", &attach_watch},
    Command{"clock", "Show this board's clock synchronisation state (kernel, chrony, PTP); --watch", &attach_clock},
    Command{"setup", "Prepare this board (gpio, irq, chrony, agent, board); --dry-run", &attach_setup},
    Command{"schedtest", "Scheduling test: cyclictest wake-up latency on the capture core", &attach_schedtest},
    Command{"synctest", "Measure the boards' clock offset from a pulse both recorded (stats, ADEV/TDEV/MTIE)", &attach_synctest},
    Command{"onsettest", "Measure the onset detectors' bias and spread on simulated gyroscope motions", &attach_onsettest},
    Command{"budget", "The error budget of a latency sample: sync, kernel, circuit and calibration terms", &attach_budget},
    Command{"packets", "Commands in a packet capture (file or live) as markers; one-way times across two captures", &attach_packets},
    Command{"mark", "Send a software marker (m2mlat-mark/1 datagram) to an agent's marker port", &attach_mark},
    Command{"bag", "Messages of named topics of a ROS 2 bag (MCAP) as markers: log time and header.stamp", &attach_bag},
    Command{"agent", "Record one node and serve its events over the agent HTTP API (docs/api.md)", &attach_agent},
    Command{"report", "Statistics, comparisons and figures (text, Markdown, CSV, JSON, HTML, pgfplots)", &attach_report},
    Command{"archive", "The lab's archive in PostgreSQL: push campaign stores, list campaigns (stats/report read it)", &attach_archive},
    Command{"help", "List the subcommands with a line on each", &attach_help},
};
}  // namespace

std::span<const Command> commands() { return kCommands; }

}  // namespace m2mlat::cli
