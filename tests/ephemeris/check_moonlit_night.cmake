# `atmo ephemeris --json` at the moonlit_night scenario's place and time
# (config/scenarios/moonlit_night.json: Innsbruck, 2024-12-15T03:00:00Z, "moon
# 38 deg up in the west (azimuth 271), sun 39 deg below the horizon", six
# hours before full Moon). Run as
#   cmake -DATMO=<atmo> -DSCENARIO=<moonlit_night.json> -P check_moonlit_night.cmake
file(READ "${SCENARIO}" scenario)
string(JSON lat GET "${scenario}" location latitude_deg)
string(JSON lon GET "${scenario}" location longitude_deg)
string(JSON height GET "${scenario}" location height_m)
string(JSON utc GET "${scenario}" utc)

execute_process(
  COMMAND "${ATMO}" ephemeris --lat ${lat} --lon ${lon} --height ${height} --utc ${utc} --json --star-name Sirius
  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "atmo ephemeris exited with ${rc}: ${err}")
endif()

# expect_between(<label> <value> <low> <high>)
function(expect_between label value low high)
  if(value GREATER_EQUAL low AND value LESS_EQUAL high)
    message(STATUS "ok   ${label} = ${value} in [${low}, ${high}]")
  else()
    message(SEND_ERROR "FAIL ${label} = ${value} not in [${low}, ${high}]")
  endif()
endfunction()

string(JSON n LENGTH "${out}" bodies)
expect_between("number of bodies" ${n} 7 7)
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  string(JSON name GET "${out}" bodies ${i} name)
  set(index_${name} ${i})
endforeach()

string(JSON moon_el GET "${out}" bodies ${index_Moon} elevation_refracted_deg)
string(JSON moon_az GET "${out}" bodies ${index_Moon} azimuth_deg)
string(JSON moon_k GET "${out}" bodies ${index_Moon} illuminated_fraction)
string(JSON moon_mag GET "${out}" bodies ${index_Moon} magnitude)
string(JSON moon_km GET "${out}" bodies ${index_Moon} distance_m)
string(JSON sun_el GET "${out}" bodies ${index_Sun} elevation_deg)
string(JSON jupiter_mag GET "${out}" bodies ${index_Jupiter} magnitude)
string(JSON tt GET "${out}" time tt)
string(JSON delta_t GET "${out}" time delta_t_s)
string(JSON tai_utc GET "${out}" time tai_minus_utc_s)
string(JSON sirius_el GET "${out}" star elevation_deg)
string(JSON sirius_v GET "${out}" star v_mag)

expect_between("Moon elevation (refracted), deg" ${moon_el} 37.5 39.0)
expect_between("Moon azimuth, deg" ${moon_az} 270.0 272.0)
expect_between("Moon illuminated fraction" ${moon_k} 0.99 1.0)
expect_between("Moon magnitude" ${moon_mag} -12.9 -12.5)
expect_between("Moon distance, m" ${moon_km} 3.6e8 3.7e8)
expect_between("Sun elevation, deg" ${sun_el} -39.5 -38.0)
expect_between("Jupiter magnitude (opposition 2024-12-07)" ${jupiter_mag} -2.9 -2.7)
expect_between("Delta T = TT - UT1, s" ${delta_t} 69.18 69.19)
expect_between("TAI - UTC, s" ${tai_utc} 37 37)
expect_between("Sirius V" ${sirius_v} -1.5 -1.4)
expect_between("Sirius elevation, deg" ${sirius_el} -90 90)
if(NOT tt STREQUAL "2024-12-15T03:01:09.184")
  message(SEND_ERROR "FAIL time.tt = ${tt}, expected 2024-12-15T03:01:09.184")
endif()
