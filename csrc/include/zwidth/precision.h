/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* zwidth/precision.h - one link-time name per precision.
 *
 * The float build (-DZW_REAL_FLOAT) and the double build share one source, but their
 * structs and arguments differ in size.  An object compiled for one precision and linked
 * against the other library would run with garbage, so in the float build every external
 * function gets the suffix _f (zw_check -> zw_check_f): the mismatch is an "undefined
 * reference" at link time instead.  Included first by status.h and real.h, hence by every
 * public header.  Callers keep writing zw_check; only the symbol changes.
 *
 * Every function with external linkage in the core and in the simulation library must be
 * listed here (tools/check_symbols.sh fails on a float-library symbol without _f and on a
 * public declaration missing from this list).
 */
#ifndef ZWIDTH_PRECISION_H
#define ZWIDTH_PRECISION_H

#ifdef ZW_REAL_FLOAT
/* batch.h */
#define zw_check_many zw_check_many_f
#define zw_device_check_many zw_device_check_many_f
/* box.h */
#define zw_box_work_init zw_box_work_init_f
#define zw_box_validate zw_box_validate_f
#define zw_box_fold zw_box_fold_f
#define zw_box_k_max zw_box_k_max_f
#define zw_box_check zw_box_check_f
#define zw_box_b_range zw_box_b_range_f
#define zw_box_k_mmax zw_box_k_mmax_f
#define zw_box_loop_work_init zw_box_loop_work_init_f
#define zw_box_loop_check zw_box_loop_check_f
#define zw_box_loop_k_max zw_box_loop_k_max_f
#define zw_box_loop_b_range zw_box_loop_b_range_f
#define zw_box_loop_k_mmax zw_box_loop_k_mmax_f
/* box_cert.h */
#define zw_box_cert_verify zw_box_cert_verify_f
#define zw_box_cert_level zw_box_cert_level_f
#define zw_box_cert_b_range zw_box_cert_b_range_f
#define zw_box_cert_k_mmax zw_box_cert_k_mmax_f
#define zw_box_cert_build zw_box_cert_build_f
/* plant_box.h */
#define zw_plant_enclose zw_plant_enclose_f
#define zw_plant_enclose2 zw_plant_enclose2_f
/* sweep.h */
#define zw_sweep_fields_init zw_sweep_fields_init_f
#define zw_sweep_check_many zw_sweep_check_many_f
/* coeffs.h */
#define zw_coeffs_init zw_coeffs_init_f
#define zw_coeffs_literal zw_coeffs_literal_f
/* device.h */
#define zw_device_init zw_device_init_f
#define zw_device_normalize zw_device_normalize_f
#define zw_device_check zw_device_check_f
#define zw_device_check_region zw_device_check_region_f
#define zw_device_spectral_radius zw_device_spectral_radius_f
#define zw_device_radius_within zw_device_radius_within_f
#define zw_device_extremes_compute zw_device_extremes_compute_f
#define zw_device_k_max zw_device_k_max_f
#define zw_device_b_range zw_device_b_range_f
#define zw_device_influence zw_device_influence_f
/* device_loop.h */
#define zw_device_loop_init zw_device_loop_init_f
#define zw_device_loop_init_plant zw_device_loop_init_plant_f
#define zw_device_loop_check zw_device_loop_check_f
#define zw_device_loop_is_stable zw_device_loop_is_stable_f
#define zw_device_loop_radius_within zw_device_loop_radius_within_f
#define zw_device_loop_spectral_radius zw_device_loop_spectral_radius_f
#define zw_device_loop_k_max zw_device_loop_k_max_f
#define zw_device_loop_b_range zw_device_loop_b_range_f
#define zw_device_loop_extremes_compute zw_device_loop_extremes_compute_f
/* extremes.h */
#define zw_extremes_compute zw_extremes_compute_f
#define zw_hyperbola_top zw_hyperbola_top_f
#define zw_corner zw_corner_f
#define zw_alpha_max zw_alpha_max_f
#define zw_beta_interval zw_beta_interval_f
/* plant.h */
#define zw_plant_init zw_plant_init_f
#define zw_plant_from_coeffs zw_plant_from_coeffs_f
#define zw_plant_eval zw_plant_eval_f
#define zw_plant_spec_from_device zw_plant_spec_from_device_f
/* loop.h */
#define zw_loop_lowpass_pole zw_loop_lowpass_pole_f
#define zw_loop_init zw_loop_init_f
#define zw_loop_init_plant zw_loop_init_plant_f
#define zw_loop_carry_gain_rounding zw_loop_carry_gain_rounding_f
#define zw_loop_poly zw_loop_poly_f
#define zw_loop_check zw_loop_check_f
#define zw_loop_is_stable zw_loop_is_stable_f
#define zw_loop_radius_within zw_loop_radius_within_f
#define zw_loop_spectral_radius zw_loop_spectral_radius_f
/* loop_limits.h */
#define zw_loop_alpha_max zw_loop_alpha_max_f
#define zw_loop_beta_intervals zw_loop_beta_intervals_f
#define zw_loop_beta_interval zw_loop_beta_interval_f
#define zw_loop_extremes_compute zw_loop_extremes_compute_f
#define zw_loop_boundary_point zw_loop_boundary_point_f
#define zw_loop_boundary_line zw_loop_boundary_line_f
/* margin.h */
#define zw_char_poly zw_char_poly_f
#define zw_spectral_radius zw_spectral_radius_f
#define zw_radius_within zw_radius_within_f
/* region.h */
#define zw_check zw_check_f
#define zw_check_region zw_check_region_f
#define zw_check_proportional zw_check_proportional_f
/* regmap.h (float on the wire in both builds, but zw_regmap holds a zw_device) */
#define zw_regmap_init zw_regmap_init_f
#define zw_regmap_init_box zw_regmap_init_box_f
#define zw_regmap_active_gains zw_regmap_active_gains_f
#define zw_regmap_set_state zw_regmap_set_state_f
#define zw_regmap_handle_pdu zw_regmap_handle_pdu_f
#define zw_regmap_read zw_regmap_read_f
#define zw_regmap_write zw_regmap_write_f
#define zw_regmap_set_consent zw_regmap_set_consent_f
#define zw_regmap_set_auth zw_regmap_set_auth_f
#define zw_regmap_set_ceilings zw_regmap_set_ceilings_f
#define zw_regmap_set_storage zw_regmap_set_storage_f
#define zw_regmap_set_word_order zw_regmap_set_word_order_f
#define zw_rm_pair_float zw_rm_pair_float_f
#define zw_rm_pair_word zw_rm_pair_word_f
#define zw_regmap_restore zw_regmap_restore_f
#define zw_regmap_image zw_regmap_image_f
#define zw_regmap_auth_message zw_regmap_auth_message_f
#define zw_cert_field zw_cert_field_f
#define zw_cert_set_field zw_cert_set_field_f
#define zw_cert_encode zw_cert_encode_f
#define zw_cert_decode zw_cert_decode_f
#define zw_box_cert_word zw_box_cert_word_f
#define zw_box_cert_encode zw_box_cert_encode_f
#define zw_box_cert_decode zw_box_cert_decode_f
#define zw_crc16_words zw_crc16_words_f
#define zw_float_to_words zw_float_to_words_f
#define zw_words_to_float zw_words_to_float_f
#define zw_reason_name zw_reason_name_f
/* ident.h */
#define zw_ident_init zw_ident_init_f
#define zw_ident_start zw_ident_start_f
#define zw_ident_step zw_ident_step_f
#define zw_ident_abort zw_ident_abort_f
#define zw_ident_running zw_ident_running_f
#define zw_ident_sample zw_ident_sample_f
/* selftest.h */
#define zw_selftest zw_selftest_f
#define zw_selftest_failures zw_selftest_failures_f
/* portable_math.h */
#define zw_expm1_portable zw_expm1_portable_f
#define zw_nextafterf_portable zw_nextafterf_portable_f
/* sim.h (host-only library zwidth_sim_f) */
#define zw_sim_init zw_sim_init_f
#define zw_sim_run zw_sim_run_f
#define zw_sim_judge zw_sim_judge_f
#define zw_sim_set_gains zw_sim_set_gains_f
/* status.h */
#define zw_status_name zw_status_name_f
/* library-internal, declared in csrc/src/internal.h */
#define zw_check_bounded zw_check_bounded_f
#define zw_radius_within_bounded zw_radius_within_bounded_f
#define zw_routh_hurwitz zw_routh_hurwitz_f
#define zw_plant_fail zw_plant_fail_f
/* library-internal, declared in csrc/src/regmap_internal.h */
#define zw_rm_publish_gains zw_rm_publish_gains_f
#define zw_rm_payload_word zw_rm_payload_word_f
#define zw_rm_payload_float zw_rm_payload_float_f
#define zw_rm_crc_word zw_rm_crc_word_f
#define zw_rm_policy_admit zw_rm_policy_admit_f
#define zw_rm_apply_gains zw_rm_apply_gains_f
#define zw_rm_live_all zw_rm_live_all_f
#define zw_rm_write_cert zw_rm_write_cert_f
#define zw_rm_command zw_rm_command_f
#define zw_rm_seal_staged zw_rm_seal_staged_f
#define zw_rm_sealed_word zw_rm_sealed_word_f
#define zw_rm_write_mac zw_rm_write_mac_f
#define zw_rm_write_box_cert zw_rm_write_box_cert_f
#define zw_rm_sealed_box_cert_word zw_rm_sealed_box_cert_word_f
#define zw_rm_save zw_rm_save_f
#endif /* ZW_REAL_FLOAT */

#endif /* ZWIDTH_PRECISION_H */
