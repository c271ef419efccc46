#pragma once
// `trueaxis campaign add`: one laser file, as it comes out of the laser software, into a campaign
// folder (docs/campaign.md "On your own machine"). Its start is put on the campaign clock (from
// the option, else the file's own date, else its modification time as the end of the test), each
// point gets the logged temperatures at its time (linear between the log's rows; refused when the
// log does not cover the test), and the file is written as canonical CSV into the folder and
// appended to manifest.json, as the fit reads it.
#include <string>
#include <vector>

namespace trueaxis::campaign {

struct CampaignAddOptions {
  std::string campaign_dir;
  std::string file;
  std::string axis;
  std::string state;    // one of measure::CampaignStates()
  std::string coolant;  // "" = from the log's coolant column during the test
  std::string start;    // date of the test's start ("" = from the file)
  std::string end;      // date of the test's end (instead of start)
};

struct CampaignAddResult {
  std::string written;       // the file written into the folder
  std::string start_source;  // "--start", "--end", "the file's date", "the file's modification time"
  std::string start_date;
  double start_time_s = 0, end_time_s = 0;  // campaign clock
  double nut_rise_c = 0;     // NaN when the axis has no nut sensor or no cold test yet
  int sequence = 0;
};

// Throws InputError naming the file, line and field (the campaign's manifest or log, the laser
// file, or the command line) for anything it cannot do exactly.
CampaignAddResult AddToCampaign(const CampaignAddOptions& options);

}  // namespace trueaxis::campaign
