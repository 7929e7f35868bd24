#!/bin/bash
# A real single-node Slurm cluster on loopback, everything under directory $1 (config, munge
# key and socket, state, logs), controller and node daemon on ports $2 and $3. For the
# campaign tests (Slurm job arrays); stop it by killing the PIDs in $1/*.pid and
# $1/munge/munged.pid. Needs root and Debian's slurmctld, slurmd, slurm-client, munge.
set -eu
D=$1; PCTL=$2; PD=$3
mkdir -p $D/munge $D/state $D/spool $D/log; chmod 755 $D
chown munge:munge $D/munge; chmod 0711 $D/munge
dd if=/dev/urandom of=$D/munge/munge.key bs=1024 count=1 2>/dev/null
chown munge:munge $D/munge/munge.key; chmod 400 $D/munge/munge.key
su -s /bin/sh munge -c "/usr/sbin/munged --key-file=$D/munge/munge.key --socket=$D/munge/munge.socket --pid-file=$D/munge/munged.pid --log-file=$D/munge/munged.log --seed-file=$D/munge/seed" 
cat > $D/slurm.conf <<EOC
ClusterName=raildyn
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$PCTL
SlurmdPort=$PD
AuthType=auth/munge
AuthInfo=socket=$D/munge/munge.socket
CryptoType=crypto/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
SchedulerType=sched/builtin
SelectType=select/cons_tres
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOC
export SLURM_CONF=$D/slurm.conf
/usr/sbin/slurmctld -f $D/slurm.conf
/usr/sbin/slurmd -f $D/slurm.conf
