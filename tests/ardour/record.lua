-- Step 2: Pneuma on the voice track, its MIDI recorded on a MIDI track, the session saved for
-- ardour7-export. Writes $PNEUMA_ARDOUR_OUT/cc.mid (the recorded region) and facts.txt.
dofile(os.getenv("PNEUMA_ARDOUR_SCRIPTS") .. "/common.lua")
local out_dir = assert(os.getenv("PNEUMA_ARDOUR_OUT"), "PNEUMA_ARDOUR_OUT not set")
start_engine()

local function record()
  open_session()

  -- The region over the whole voice file run.sh put in place of the recording.
  local voice = track("Voice")
  local region = only_region(voice)
  local length = region:source(0):length():samples()
  region:trim_to(Temporal.timepos_t(0), Temporal.timecnt_t(length))
  check(region:length():samples() == length, "the region does not cover the voice")
  Session:locations():session_range_location():set(Temporal.timepos_t(0), Temporal.timepos_t(length))
  -- Only the CC track records (Ardour may bring the voice track back armed from step 1). A track
  -- that is not armed plays silence while the session records unless it monitors disk.
  voice:rec_enable_control():set_value(0, PBD.GroupControlDisposition.NoGroup)
  voice:monitoring_control():set_value(ARDOUR.MonitorChoice.MonitorDisk,
    PBD.GroupControlDisposition.NoGroup)
  -- With strict I/O Ardour gives an audio track no MIDI output port for the plugin's CC.
  voice:set_strict_io(false)
  local pneuma = ARDOUR.LuaAPI.new_plugin(Session, "Pneuma", ARDOUR.PluginType.VST3, "")
  check(not pneuma:isnil(), "Ardour does not know Pneuma.vst3 (scan it with ardour-vst3-scanner)")
  voice:add_processor_by_index(pneuma, 0, nil, true)
  sleep_s(0.2)
  local latency = pneuma:signal_latency()
  check(voice:output():n_ports():n_midi() == 1, "the voice track has no MIDI output")

  local midi = ARDOUR.ChanCount(ARDOUR.DataType("midi"), 1)
  Session:new_midi_track(midi, midi, false, ARDOUR.PluginInfo(), nil, nil, 1, "CC",
    ARDOUR.PresentationInfo.max_order, ARDOUR.TrackMode.Normal, true)
  local cc = track("CC")
  cc:input():disconnect_all(nil)
  check(cc:input():midi(0):connect(voice:output():midi(0):name()) == 0,
    "cannot connect the voice track's MIDI output to the CC track")
  cc:rec_enable_control():set_value(1, PBD.GroupControlDisposition.NoGroup)
  Session:maybe_enable_record(false)
  roll_to(length + RATE)
  Session:disable_record(false, false)
  cc:rec_enable_control():set_value(0, PBD.GroupControlDisposition.NoGroup)
  check(only_region(voice):length():samples() == length, "the voice track recorded over the voice")
  wait_for_region(cc)
  local take = only_region(cc)
  check(take:to_midiregion():do_export(out_dir .. "/cc.mid"), "cannot export the recorded MIDI")

  local facts = io.open(out_dir .. "/facts.txt", "w")
  facts:write("voice_samples=" .. length .. "\n")
  facts:write("lookahead_latency_samples=" .. latency .. "\n")
  facts:write("cc_region_position_samples=" .. take:position():samples() .. "\n")
  facts:close()
  save()
end

record()
close()
print("DONE")
