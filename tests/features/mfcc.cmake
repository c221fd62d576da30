# MFCC against SPTK 3.9's `mfcc`, run at test time (owned by the audio/MFCC work; included from CMakeLists.txt).
talkinghead_add_test(mfcc_sptk_test SOURCES mfcc_sptk_test.cpp LABELS unit)
